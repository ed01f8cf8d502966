"""Multi-fidelity evaluation: the analytic criteria screen a batch, the cut simulation judges
the most promising plans of it.

Under ``criteria: simulated`` with ``simulation: {screening: {...}}`` one batch of n plans is
evaluated in rounds:

1. every plan gets its analytic Eq. 9 objective ``a`` (``criteria/analytic.py``, a few ms a
   plan) and a prediction of its simulated objective, ``p = a + c``, with ``c`` the
   correction learned from the pairs (analytic, simulated) this run has simulated so far;
2. the ``ceil(fraction n)`` plans of lowest ``p`` are simulated (``criteria/simulated.py``);
   With ``correction: nearest``, so is the best-predicted plan of each tool (and strategy)
   of the batch that has no simulated plan yet (at most one simulation per tool in a run);
3. every plan not yet simulated whose prediction, re-made with the new pairs, is at or below
   the best simulated objective so far (the **elite**: a plan that could become the run's
   best) is simulated too; step 3 repeats until no such plan is left.

A simulated plan's value is its simulated objective; the others get their prediction, which
is then above the best simulated value the run has been given. So the run's best (its
``best.json``) is always a simulated plan, and the evaluation budget, which counts the
``cost`` of each row (1 simulated, 0 screened: ``evoplan/engine.py``), counts simulations.

**Correction** (``correction``): ``nearest`` (default) adds to ``a`` the inverse-distance
weighted mean residual ``s - a`` of the ``neighbours`` nearest simulated plans with the same
tool (and strategy), distances over the other free genes scaled to their ranges; without
such a plan, the ``offset``. ``offset`` adds the median residual of every simulated plan (0
before the first). The analytic model ranks random plans as the simulation does (Spearman
0.85-0.97, the grid's resolution decides), but its error is not a constant: the pose gouge
and the chord error it adds up are upper bounds whose slack depends on the tool and its
lean, so a residual learned near a plan beats one offset for all (on 100 random Fountas
plans at a 1 mm grid, held-out RMS error 0.089 against 0.109 in Eq. 9 units); and a run
concentrates its plans, where its nearest pairs get close.

The correction's pairs live in this object, not in the run's checkpoint: a resumed run
relearns them from the simulations after the resume (its best stays a simulated plan).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from .objective import weighted_sum

__all__ = ["Screening", "ScreeningSettings", "CORRECTIONS", "settings_error"]

#: ways to predict a plan's simulated objective from its analytic one
CORRECTIONS = ("nearest", "offset")

#: genes compared by equality (categories), not by distance
_CATEGORICAL = ("tool", "strategy")


class ScreeningSettings(BaseModel):
    """A run file's ``simulation.screening`` mapping (module docstring); unknown keys are
    refused."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    fraction: float = Field(0.25, description="the share of each batch simulated, the elite "
                            "aside; in (0, 1] (1 simulates every plan, as without screening)")
    correction: Literal["nearest", "offset"] = Field(
        "nearest", description="how a plan's simulated objective is predicted from its analytic one")
    neighbours: int = Field(3, description="simulated plans the nearest correction averages (>= 1)")

    @model_validator(mode="before")
    @classmethod
    def _mapping(cls, data):
        if not isinstance(data, (dict, ScreeningSettings)):
            raise ValueError(f"expected a mapping (fraction, correction, neighbours), got {data!r}")
        return data

    @field_validator("fraction", mode="before")
    @classmethod
    def _fraction(cls, v):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 < v <= 1:
            raise ValueError(f"expected a number in (0, 1], got {v!r}")
        return float(v)

    @field_validator("correction", mode="before")
    @classmethod
    def _correction(cls, v):
        if v not in CORRECTIONS:
            raise ValueError(f"expected {' or '.join(CORRECTIONS)}, got {v!r}")
        return v

    @field_validator("neighbours", mode="before")
    @classmethod
    def _neighbours(cls, v):
        return at_least_one(v)


def at_least_one(value, of: str = "") -> int:
    """An integer >= 1 (a bool or a float refused); ``of`` names what it counts."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"expected a whole number{of} >= 1, got {value!r}")
    return value


def settings_error(error, key: str, models: dict) -> str:
    """One line ``key.path: message`` of a settings model's ``ValidationError``; ``models``:
    location below ``key`` -> the model there, whose keys an unknown key's hint lists as
    ``unknown setting (known: ...)``."""
    from ..spec.errors import Known, one_line  # spec builds on this module: imported at the call

    def known(loc):
        model = models.get(tuple(loc))
        return None if model is None else Known.settings(model)
    return one_line(error, key, known)


class Screening:
    """The screening of a batch by the analytic criteria (module docstring), with the pairs
    it has learned from.

    ``settings``: a :class:`ScreeningSettings` (a plain mapping is validated into one, its
    errors starting with ``key``).
    """

    def __init__(self, settings: ScreeningSettings | dict | None = None,
                 key: str = "simulation.screening") -> None:
        if not isinstance(settings, ScreeningSettings):
            try:
                settings = ScreeningSettings.model_validate({} if settings is None else settings)
            except ValidationError as e:
                raise ValueError(settings_error(e, key, {(): ScreeningSettings})) from None
        self.settings = settings
        self.fraction = settings.fraction
        self.correction = settings.correction
        self.neighbours = settings.neighbours
        self.best = math.inf  # the best simulated objective returned so far
        self.simulations = 0
        self.screened = 0  # plans valued by their prediction alone
        self._z = np.zeros((0, 0))  # the simulated plans' scaled continuous genes
        self._cat = np.zeros((0, 0))  # ... their categorical genes
        self._residual = np.zeros(0)  # ... their simulated minus analytic objective

    # -- the correction -----------------------------------------------------------------
    @staticmethod
    def _features(problem, X) -> tuple[np.ndarray, np.ndarray]:
        """(continuous genes scaled to [0, 1] by their ranges, categorical genes) of X."""
        free = problem.genes.free
        cat = np.array([name in _CATEGORICAL for name in free], bool)
        span = np.where(problem.xu > problem.xl, problem.xu - problem.xl, 1.0)
        z = (X - problem.xl) / span
        return z[:, ~cat], np.rint(X[:, cat])

    def _offset(self) -> float:
        return float(np.median(self._residual)) if self._residual.size else 0.0

    def predict(self, a: np.ndarray, z: np.ndarray, cat: np.ndarray) -> np.ndarray:
        """The predicted simulated objective of plans of analytic objective ``a``."""
        offset = self._offset()
        if self.correction == "offset" or not self._residual.size:
            return a + offset
        same = (cat[:, None, :] == self._cat[None, :, :]).all(axis=2)  # (n, m)
        d = np.sqrt(((z[:, None, :] - self._z[None, :, :]) ** 2).sum(axis=2))
        d = np.where(same, d, np.inf)
        k = min(self.neighbours, d.shape[1])
        near = np.argsort(d, axis=1, kind="stable")[:, :k]
        dn = np.take_along_axis(d, near, axis=1)
        w = np.where(np.isfinite(dn), 1.0 / (dn + 1e-9), 0.0)
        has = w.sum(axis=1) > 0
        local = (w * self._residual[near]).sum(axis=1) / np.where(has, w.sum(axis=1), 1.0)
        return a + np.where(has, local, offset)

    def _untried(self, cat: np.ndarray, p: np.ndarray) -> np.ndarray:
        """The best-predicted plan of each tool (and strategy) of the batch of which no plan
        has been simulated yet: without a pair of its own a category gets the offset of the
        others, and the analytic bias differs by tool, so one simulation each learns it."""
        out = np.zeros(len(p), bool)
        if cat.shape[1] == 0:
            return out
        known = {tuple(row) for row in self._cat.tolist()} if self._cat.shape[1] == cat.shape[1] else set()
        best: dict = {}
        for i, row in enumerate(map(tuple, cat.tolist())):
            if row not in known and np.isfinite(p[i]) and (row not in best or p[i] < p[best[row]]):
                best[row] = i
        out[list(best.values())] = True
        return out

    def _learn(self, z, cat, residual) -> None:
        if self._z.shape[1] != z.shape[1] or self._cat.shape[1] != cat.shape[1]:
            self._z, self._cat = np.zeros((0, z.shape[1])), np.zeros((0, cat.shape[1]))
        self._z = np.concatenate([self._z, z])
        self._cat = np.concatenate([self._cat, cat])
        self._residual = np.concatenate([self._residual, residual])

    # -- a batch --------------------------------------------------------------------------
    def evaluate(self, problem, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(F (n, 1), cost (n,))`` of the checked rows X of ``problem`` (a ToolpathProblem
        under ``criteria: simulated``): F the simulated objective of the plans simulated and
        the prediction of the others, cost 1 for a simulated plan and 0 for a screened one."""
        if problem.objectives is not None:
            raise ValueError("simulation.screening: ranks plans by one objective (weights), not by objectives")
        n = len(X)
        if n == 0:
            return np.zeros((0, 1)), np.zeros(0)
        crit, genes = problem.analytic(X)
        a = weighted_sum(crit, problem.weights, problem.norm_bounds)
        z, cat = self._features(problem, X)
        p = self.predict(a, z, cat)
        f = np.where(np.isfinite(p), p, np.inf)
        done = np.zeros(n, bool)
        take = np.zeros(n, bool)
        order = np.argsort(np.where(np.isfinite(p), p, np.inf), kind="stable")
        take[order[: math.ceil(self.fraction * n)]] = True
        if self.correction == "nearest":
            take |= self._untried(cat, f)
        while take.any():
            rows = np.flatnonzero(take)
            sim = {k: v[rows] for k, v in crit.items()} | problem.simulate_rows(genes, rows)
            s = weighted_sum(sim, problem.weights, problem.norm_bounds)
            f[rows], done[rows] = s, True
            ok = np.isfinite(s) & np.isfinite(a[rows])
            self._learn(z[rows][ok], cat[rows][ok], (s - a[rows])[ok])
            if np.isfinite(s).any():
                self.best = min(self.best, float(np.min(s[np.isfinite(s)])))
            rest = np.flatnonzero(~done)
            f[rest] = self.predict(a[rest], z[rest], cat[rest])
            take[:] = False
            take[rest] = f[rest] <= self.best  # the elite: could become the run's best
        self.simulations += int(done.sum())
        self.screened += int(n - done.sum())
        return f[:, None], done.astype(float)
