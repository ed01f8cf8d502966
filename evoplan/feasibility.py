"""pymoo's view of a run's optimum: the best *feasible* point, or nothing.

evoplan's engine ranks a constrained problem by its penalized objective (``f + penalty *
violation``, :mod:`evoplan.evaluation`), so its best point may violate the constraints: on g1
after a few generations it is a point with ``f`` near ``7e7``. pymoo instead reports the best
feasible point (``CV <= 0``) and ``X = F = None`` when it has found none
(:func:`pymoo.util.optimum.filter_optimum`). :class:`FeasibleBest` watches every evaluation of
a run (it wraps the evaluator the engine calls) and keeps that point, so that
:class:`evoplan.api.Result` can report both views.
"""

from __future__ import annotations

import numpy as np

from .evaluation import Evaluation
from .multiobjective import Ledger


class FeasibleBest:
    """An evaluator that passes batches on and keeps the best feasible row it has seen.

    ``X``: the row (decoded, as the problem takes it), ``F``: its objective before any penalty,
    ``CV``: its pymoo constraint violation; all ``None`` until a feasible row was evaluated.
    Every other attribute is the wrapped evaluator's.
    """

    def __init__(self, evaluator) -> None:
        self.evaluator = evaluator
        self.X: np.ndarray | None = None
        self.F: float | None = None
        self.CV: float | None = None
        self.feasible_rows: set[bytes] = set()  # several objectives: the feasible rows, by their bytes

    def __getattr__(self, name):
        return getattr(self.__dict__["evaluator"], name)

    def __call__(self, X: np.ndarray) -> Evaluation:
        result = self.evaluator(X)
        if result.cv is not None and result.F is not None:
            ok = (result.cv <= 0) & ~result.failed
            self.feasible_rows.update(Ledger.keys(X[ok]))
        if result.cv is not None and result.raw is not None:
            ok = (result.cv <= 0) & ~result.failed & np.isfinite(result.raw)
            if ok.any():
                i = int(np.argmin(np.where(ok, result.raw, np.inf)))
                if self.F is None or result.raw[i] < self.F:
                    self.X, self.F, self.CV = np.array(X[i], dtype=float), float(result.raw[i]), float(result.cv[i])
        return result


def pymoo_arrays(problem, tracker: FeasibleBest | None, best_X: np.ndarray | None, best_f: float,
                 front=None) -> dict:
    """``X``, ``F``, ``CV`` and ``feasible`` shaped as pymoo's ``Result`` shapes them.

    One objective: ``X (n_var,)``, ``F (1,)``, ``CV (1,)`` of the best feasible point (an
    unconstrained problem's every point is feasible, ``CV = 0``); several objectives: the
    non-dominated set, ``X (k, n_var)``, ``F (k, n_obj)``, ``CV (k, 1)`` (constrained: its
    feasible points; the archive is kept on penalized vectors, so a feasible point dominated
    only by an infeasible one is missing, where pymoo would list it). Nothing feasible
    (or nothing evaluated without failing): ``X = F = CV = None`` and ``feasible`` False.
    """
    constrained = bool(problem.n_ieq_constr or problem.n_eq_constr)
    if front is not None:
        X, F = np.asarray(front[0], dtype=float), np.asarray(front[1], dtype=float)
        if constrained:  # the front's feasible points (the penalty ranks infeasible ones behind)
            rows = tracker.feasible_rows if tracker is not None else set()
            keep = np.array([k in rows for k in Ledger.keys(X)], dtype=bool) if len(X) else np.zeros(0, dtype=bool)
            X, F = X[keep], F[keep]
        if not len(F):
            return {"X": None, "F": None, "CV": None, "feasible": False}
        return {"X": np.array(X, dtype=float), "F": np.array(F, dtype=float), "CV": np.zeros((len(F), 1)),
                "feasible": True}
    if constrained:
        if tracker is None or tracker.X is None:
            return {"X": None, "F": None, "CV": None, "feasible": False}
        return {"X": tracker.X.copy(), "F": np.array([tracker.F]), "CV": np.array([tracker.CV]), "feasible": True}
    if best_X is None or not np.isfinite(best_f):
        return {"X": None, "F": None, "CV": None, "feasible": False}
    return {"X": np.array(best_X, dtype=float), "F": np.array([best_f]), "CV": np.zeros(1), "feasible": True}
