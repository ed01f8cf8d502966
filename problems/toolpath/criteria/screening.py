"""Multi-fidelity evaluation: the analytic criteria screen a batch, the cut simulation judges
the most promising plans of it.

Under ``criteria: simulated`` with ``simulation: {screening: {...}}`` one batch of n plans is
evaluated in rounds:

1. every plan gets its analytic criteria and Eq. 9 objective ``a`` (``criteria/analytic.py``,
   a few ms a plan) and a prediction ``p`` of its simulated objective, corrected by what
   the pairs (analytic, simulated) this run has simulated so far teach;
2. the ``ceil(fraction n)`` plans of lowest ``p`` are simulated (``criteria/simulated.py``),
   those of them predicted within a margin of the best simulated objective so far: the
   ``error_quantile`` (default 0.5) of the screen's last 50 prediction errors (what the
   simulation of a plan found minus its prediction, in absolute value), once 10 are known
   (``error_quantile: null`` or ``fraction: 1``: no margin, the whole fraction). A batch
   with nothing that promising costs no simulation. With a local correction (``ratio``,
   ``nearest``), the best-predicted plan of each tool (and strategy) of the batch that has
   no simulated plan yet is simulated too (at most one simulation per tool in a run);
3. every plan not yet simulated whose prediction, re-made with the new pairs, is at or below
   the best simulated objective so far (the **elite**: a plan that could become the run's
   best) is simulated too; step 3 repeats until no such plan is left.

A simulated plan's value is its simulated objective; the others get their prediction, which
is then above the best simulated value the run has been given. So the run's best (its
``best.json``) is always a simulated plan, and the evaluation budget, which counts the
``cost`` of each row (1 simulated, 0 screened: ``evoplan/engine.py``), counts simulations.

**Correction** (``correction``), each learned from the ``neighbours`` nearest simulated
plans with the same tool (and strategy), inverse-distance weighted, distances over the other
free genes scaled to their ranges; a plan with no such neighbour takes the median of every
pair (and, before the first pair, nothing):

- ``ratio`` (default) scales each simulated criterion the objective weighs (the machining
  error, a scallop, a gouge) by the neighbours' ratio simulated / analytic of it (a mean of
  log ratios, each value plus ``RATIO_FLOOR``), then forms Eq. 9 from the scaled criteria;
- ``nearest`` adds to ``a`` the neighbours' residual ``s - a`` of the objective;
- ``offset`` adds the median residual of every simulated plan.

The analytic model ranks random plans as the simulation does, but its error is neither a
constant nor an additive one: its cusp heights and pose gouge are upper bounds whose slack
grows with the deviation and depends on the tool and its lean, so a scale learned near a
plan transfers to its neighbours where a residual does not. Held out one at a time on 150
random Fountas plans at a 1 mm grid (``runs/bench/screening_corrections.py``), the Eq. 9
prediction errors of the best 30 % are, RMS, 0.010 (ratio), 0.055 (nearest) and 0.10
(offset) with the mean machining error in Eq. 9, and 0.028, 0.069 and 0.082 with the
largest one (which the 1 mm grid samples below the cusps' tops: see
``runs/bench/screening.md``).

The correction's pairs and the prediction errors live in this object, not in the run's
checkpoint: a resumed run relearns them from the simulations after the resume (its best
stays a simulated plan).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from .objective import weighted_sum

__all__ = ["Screening", "ScreeningSettings", "CORRECTIONS", "settings_error"]

#: ways to predict a plan's simulated objective from its analytic one
CORRECTIONS = ("ratio", "nearest", "offset")

#: the prediction errors the margin of :meth:`Screening.margin` is a quantile of (the
#: latest), and how many it needs first
ERROR_WINDOW, ERROR_MIN = 50, 10

#: mm added to a simulated and an analytic criterion before their ratio: the ratio of two
#: near-zero deviations (a plan that leaves no gouge) is noise, not a scale
RATIO_FLOOR = 1e-3

#: genes compared by equality (categories), not by distance
_CATEGORICAL = ("tool", "strategy")


class ScreeningSettings(BaseModel):
    """A run file's ``simulation.screening`` mapping (module docstring); unknown keys are
    refused."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    fraction: float = Field(0.25, description="the share of each batch simulated, the elite "
                            "aside; in (0, 1] (1 simulates every plan, as without screening)")
    correction: Literal["ratio", "nearest", "offset"] = Field(
        "ratio", description="how a plan's simulated objective is predicted from its analytic one")
    neighbours: int = Field(3, description="simulated plans the nearest correction averages (>= 1)")
    error_quantile: float | None = Field(
        0.5, description="simulate the fraction only where its prediction is within this quantile "
                         "of the screen's recent prediction errors of the best; in (0, 1], null: always")

    @model_validator(mode="before")
    @classmethod
    def _mapping(cls, data):
        if not isinstance(data, (dict, ScreeningSettings)):
            raise ValueError(f"expected a mapping (fraction, correction, neighbours, error_quantile), "
                             f"got {data!r}")
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
            raise ValueError(f"expected {', '.join(CORRECTIONS[:-1])} or {CORRECTIONS[-1]}, got {v!r}")
        return v

    @field_validator("error_quantile", mode="before")
    @classmethod
    def _quantile(cls, v):
        if v is None:
            return None
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 < v <= 1:
            raise ValueError(f"expected a number in (0, 1] or null, got {v!r}")
        return float(v)

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
        self.error_quantile = settings.error_quantile
        self._errors: list[float] = []  # |simulated - predicted| of the latest plans simulated
        self.best = math.inf  # the best simulated objective returned so far
        self.simulations = 0
        self.screened = 0  # plans valued by their prediction alone
        self._z = np.zeros((0, 0))  # the simulated plans' scaled continuous genes
        self._cat = np.zeros((0, 0))  # ... their categorical genes
        self._y = np.zeros((0, 1))  # ... what the correction learned of each (``_targets``)
        self._names = None  # the simulated criteria the ratio correction scales

    # -- the correction -----------------------------------------------------------------
    @staticmethod
    def _features(problem, X) -> tuple[np.ndarray, np.ndarray]:
        """(continuous genes scaled to [0, 1] by their ranges, categorical genes) of X."""
        free = problem.genes.free
        cat = np.array([name in _CATEGORICAL for name in free], bool)
        span = np.where(problem.xu > problem.xl, problem.xu - problem.xl, 1.0)
        z = (X - problem.xl) / span
        return z[:, ~cat], np.rint(X[:, cat])

    def _local(self, z: np.ndarray, cat: np.ndarray) -> np.ndarray:
        """(n, k): the inverse-distance weighted mean target of the ``neighbours`` nearest
        simulated plans of the same categories, or the median target of all pairs where no
        pair shares them (0 before the first pair; the median alone for ``offset``)."""
        n, k = len(z), self._y.shape[1]
        if not len(self._y):
            return np.zeros((n, k))
        offset = np.median(self._y, axis=0)
        if self.correction == "offset":
            return np.broadcast_to(offset, (n, k)).copy()
        same = (cat[:, None, :] == self._cat[None, :, :]).all(axis=2)  # (n, m)
        d = np.sqrt(((z[:, None, :] - self._z[None, :, :]) ** 2).sum(axis=2))
        d = np.where(same, d, np.inf)
        near = np.argsort(d, axis=1, kind="stable")[:, :min(self.neighbours, d.shape[1])]
        dn = np.take_along_axis(d, near, axis=1)
        w = np.where(np.isfinite(dn), 1.0 / (dn + 1e-9), 0.0)
        total = w.sum(axis=1)
        local = (w[:, :, None] * self._y[near]).sum(axis=1) / np.where(total > 0, total, 1.0)[:, None]
        return np.where((total > 0)[:, None], local, offset)

    def predict(self, problem, crit: dict, a: np.ndarray, z: np.ndarray, cat: np.ndarray) -> np.ndarray:
        """The predicted simulated objective of plans of analytic criteria ``crit`` and
        analytic objective ``a`` (module docstring: the corrections)."""
        if self.correction == "ratio" and self._names is None:
            return a.copy()  # no pair yet: the analytic value as it is
        local = self._local(z, cat)
        if self.correction != "ratio":
            return a + local[:, 0]
        scaled = dict(crit)
        for c, name in enumerate(self._names):
            scaled[name] = (crit[name] + RATIO_FLOOR) * np.exp(local[:, c]) - RATIO_FLOOR
        return weighted_sum(scaled, problem.weights, problem.norm_bounds)

    def _targets(self, problem, crit: dict, measured: dict, a, s) -> np.ndarray:
        """(m, k) what the correction learns from simulated plans: the residual s - a of the
        objective, or for ``ratio`` the log ratio of each simulated criterion (``measured``)
        the objective weighs to its analytic value (floored by ``RATIO_FLOOR``)."""
        if self.correction != "ratio":
            return (s - a)[:, None]
        if self._names is None:
            self._names = tuple(n for n in problem.weights if n in measured and problem.weights[n] != 0)
        y = np.empty((len(s), len(self._names)))  # no column: an objective of no simulated criterion
        for c, name in enumerate(self._names):
            y[:, c] = np.log((measured[name] + RATIO_FLOOR) / (crit[name] + RATIO_FLOOR))
        return y

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

    def _learn(self, z, cat, y) -> None:
        y = np.asarray(y, float).reshape(len(z), -1)
        if self._z.shape[1] != z.shape[1] or self._cat.shape[1] != cat.shape[1] \
                or self._y.shape[1] != y.shape[1]:
            self._z, self._cat = np.zeros((0, z.shape[1])), np.zeros((0, cat.shape[1]))
            self._y = np.zeros((0, y.shape[1]))
        self._z = np.concatenate([self._z, z])
        self._cat = np.concatenate([self._cat, cat])
        self._y = np.concatenate([self._y, y])

    # -- pairs and predictions -------------------------------------------------------------
    def learn(self, problem, X: np.ndarray, crit: dict, measured: dict) -> np.ndarray:
        """Learn from the simulated rows X of ``problem``: ``crit`` their analytic criteria,
        ``measured`` their simulated ones (dicts of (m,)). Returns their simulated objective."""
        a = weighted_sum(crit, problem.weights, problem.norm_bounds)
        s = weighted_sum(crit | measured, problem.weights, problem.norm_bounds)
        z, cat = self._features(problem, X)
        y = self._targets(problem, crit, measured, a, s)
        ok = np.isfinite(s) & np.isfinite(a) & np.isfinite(y).all(axis=1)
        self._learn(z[ok], cat[ok], y[ok])
        return s

    def predicted(self, problem, X: np.ndarray, crit: dict) -> np.ndarray:
        """The predicted simulated objective of the rows X of analytic criteria ``crit``."""
        a = weighted_sum(crit, problem.weights, problem.norm_bounds)
        z, cat = self._features(problem, X)
        return self.predict(problem, crit, a, z, cat)

    def margin(self) -> float:
        """How far above the best simulated objective a plan of the fraction may be predicted
        and still be simulated: the ``error_quantile`` of the last ``ERROR_WINDOW``
        prediction errors once ``ERROR_MIN`` are known, else (and with ``fraction`` 1 or no
        quantile) no limit."""
        if self.error_quantile is None or self.fraction >= 1 or len(self._errors) < ERROR_MIN \
                or not np.isfinite(self.best):
            return math.inf
        return float(np.quantile(self._errors, self.error_quantile))

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

        def pick(rows):
            return {k: v[rows] for k, v in crit.items()}
        p = self.predicted(problem, X, crit)
        f = np.where(np.isfinite(p), p, np.inf)
        done = np.zeros(n, bool)
        take = np.zeros(n, bool)
        take[np.argsort(f, kind="stable")[: math.ceil(self.fraction * n)]] = True
        take &= f <= self.best + self.margin()
        if self.correction != "offset":
            take |= self._untried(self._features(problem, X)[1], f)
        while take.any():
            rows = np.flatnonzero(take)
            s = self.learn(problem, X[rows], pick(rows), problem.simulate_rows(genes, rows))
            miss = np.abs(s - f[rows])
            self._errors = (self._errors + miss[np.isfinite(miss)].tolist())[-ERROR_WINDOW:]
            f[rows], done[rows] = s, True
            if np.isfinite(s).any():
                self.best = min(self.best, float(np.min(s[np.isfinite(s)])))
            rest = np.flatnonzero(~done)
            f[rest] = self.predicted(problem, X[rest], pick(rest))
            take[:] = False
            take[rest] = f[rest] <= self.best  # the elite: could become the run's best
        self.simulations += int(done.sum())
        self.screened += int(n - done.sum())
        return f[:, None], done.astype(float)
