"""Multi-objective runs: vector evaluation, the non-dominated archive, hypervolume, Pareto files.

A problem with ``n_obj > 1`` (the toolpath problem with ``objectives: [machining_error,
machining_time]``) is evaluated by :class:`MultiEvaluator`. The engine keeps counting, caching
and checkpointing as for one objective: it sees the *scalar* ``f = F @ w``, Fountas Eq. 9's
weighted sum over the objectives (``w`` from the problem's ``weights`` restricted to its
``objectives``, else equal weights), so ``best`` in ``history.csv`` is the best weighted sum
found. The objective *vectors* go to a :class:`Ledger` (phenotype row -> ``F`` row) that the
multi-objective algorithm (:mod:`evoplan.adapters.pymoo_multi`) reads when it is told, and
that travels inside the algorithm (so a checkpoint holds it and a cache hit still finds its
vector).

Non-dominance and the hypervolume are moocore's (:func:`moocore.is_nondominated`,
:func:`moocore.hypervolume`), the implementation pymoo's own ``HV`` indicator builds on.
"""

from __future__ import annotations

import numpy as np

from .evaluation import Evaluation, Evaluator, violations

__all__ = ["Ledger", "MultiEvaluator", "scalarization_weights", "nondominated", "hypervolume",
           "reference_point", "connect"]


def scalarization_weights(problem) -> np.ndarray:
    """Eq. 9 weights of the objective columns: the problem's ``weights`` on its ``objectives``.

    Weights named for criteria that are not objectives are dropped and the rest rescaled to
    sum 1; with no usable weights every objective weighs the same.
    """
    k = int(problem.n_obj)
    names = getattr(problem, "objectives", None) or []
    weights = getattr(problem, "weights", None) or {}
    w = np.array([float(weights.get(n, 0.0)) for n in names]) if len(names) == k else np.zeros(k)
    return w / w.sum() if w.sum() > 0 else np.full(k, 1.0 / k)


def objective_names(problem) -> list[str]:
    names = getattr(problem, "objectives", None)
    return list(names) if names and len(names) == problem.n_obj else [f"f{i + 1}" for i in range(problem.n_obj)]


class Ledger:
    """Objective vectors by phenotype row (the bytes of the float64 row), in insertion order."""

    def __init__(self) -> None:
        self.rows: dict[bytes, np.ndarray] = {}

    @staticmethod
    def keys(X: np.ndarray) -> list[bytes]:
        X = np.ascontiguousarray(np.atleast_2d(X), dtype=np.float64)
        return [row.tobytes() for row in X]

    def store(self, X: np.ndarray, F: np.ndarray) -> None:
        for key, row in zip(self.keys(X), F):
            self.rows[key] = np.array(row, dtype=float)

    def lookup(self, X: np.ndarray, n_obj: int) -> np.ndarray:
        """``F: (n, n_obj)`` of the rows of ``X``; a row never evaluated is ``inf``."""
        missing = np.full(n_obj, np.inf)
        return np.array([self.rows.get(k, missing) for k in self.keys(X)]).reshape(-1, n_obj)


class MultiEvaluator(Evaluator):
    """``X -> Evaluation`` whose ``f`` is the weighted sum; the vectors go to :attr:`ledger`.

    Constraints add ``penalty * violation`` to every objective. A row that raises or gives a
    non-finite objective is a failure (``inf`` everywhere), as in the single-objective
    :class:`~evoplan.evaluation.Evaluator`, whose row-by-row isolation this reuses.
    """

    def __init__(self, problem, constraint_penalty: float = 1e6) -> None:
        if problem.n_obj < 2:
            raise ValueError("a multi-objective evaluator needs at least two objectives")
        self.problem = problem
        self.constraint_penalty = float(constraint_penalty)
        self.constrained = bool(problem.n_ieq_constr or problem.n_eq_constr)
        self.weights = scalarization_weights(problem)
        self.ledger = Ledger()

    def vectors(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """The (penalized) objective vectors of ``X`` and pymoo's ``CV`` (None: unconstrained)."""
        out = self.problem.evaluate(X, return_as_dictionary=True)
        F = np.asarray(out["F"], dtype=float).reshape(len(X), -1)
        if not self.constrained:
            return F, None
        penalized, cv = violations(self.problem, out, len(X))
        return F + self.constraint_penalty * penalized[:, None], cv

    def _values(self, X: np.ndarray) -> tuple[np.ndarray, None, np.ndarray | None]:
        F, cv = self.vectors(X)
        bad = ~np.isfinite(F).all(axis=1)
        F[bad] = np.inf
        self._batch.store(X, F)
        with np.errstate(invalid="ignore"):
            return np.where(bad, np.nan, np.nan_to_num(F, posinf=0.0) @ self.weights), None, cv

    def __call__(self, X: np.ndarray) -> Evaluation:
        """The scalar evaluation, with the batch's vectors in ``F`` (``inf`` rows for non-finite
        ones, NaN rows for rows that raised); the vectors are stored in :attr:`ledger` too (where this evaluator runs: a
        worker's copy is refilled in the main process by :class:`VectorsToLedger`)."""
        self._batch = Ledger()
        try:
            result = super().__call__(X)
        finally:
            batch, self._batch = self._batch, None
        for key, row in batch.rows.items():
            self.ledger.rows[key] = row
        missing = np.full(self.problem.n_obj, np.nan)  # a row that raised: not in the ledger
        result.F = np.array([batch.rows.get(k, missing) for k in Ledger.keys(X)]).reshape(len(X), -1)
        return result


class VectorsToLedger:
    """A (parallel) evaluator of a :class:`MultiEvaluator`: the vectors its workers computed
    (``Evaluation.F``) go into the main process's ledger, in row order, as a serial run's do."""

    def __init__(self, evaluator, multi: MultiEvaluator) -> None:
        self.evaluator, self.multi = evaluator, multi

    def __call__(self, X: np.ndarray) -> Evaluation:
        result = self.evaluator(X)
        if result.F is not None:
            kept = ~np.isnan(result.F).any(axis=1)  # NaN: the row raised (a serial run keeps none)
            self.multi.ledger.store(X[kept], result.F[kept])
        return result


def connect(evaluator, algorithm, decode) -> None:
    """Let a multi-objective ``algorithm`` read the vectors ``evaluator`` computes.

    Called when a run starts or resumes: the ledger lives in the algorithm (checkpointed with
    it), the evaluator writes into it, and ``decode`` turns the algorithm's rows into the
    phenotype rows the ledger is keyed by.
    """
    if isinstance(evaluator, MultiEvaluator) and hasattr(algorithm, "ledger"):
        evaluator.ledger = algorithm.ledger
        algorithm.decode = decode


def nondominated(F: np.ndarray) -> np.ndarray:
    """Mask of the rows of ``F`` no other row dominates (minimization; non-finite rows False)."""
    import moocore

    F = np.asarray(F, dtype=float)
    ok = np.isfinite(F).all(axis=1)
    mask = np.zeros(len(F), dtype=bool)
    if ok.any():
        mask[np.flatnonzero(ok)] = moocore.is_nondominated(F[ok], maximise=False, keep_weakly=False)
    return mask


def reference_point(F: np.ndarray) -> np.ndarray:
    """The hypervolume reference: the worst finite value of each objective plus 10 % of its range."""
    F = np.asarray(F, dtype=float)
    F = F[np.isfinite(F).all(axis=1)]
    if not len(F):
        return None
    hi, lo = F.max(axis=0), F.min(axis=0)
    span = np.where(hi > lo, hi - lo, np.maximum(np.abs(hi), 1.0))
    return hi + 0.1 * span


def hypervolume(F: np.ndarray, ref: np.ndarray) -> float:
    """Hypervolume dominated by the finite rows of ``F`` and bounded by ``ref`` (moocore)."""
    import moocore

    F = np.asarray(F, dtype=float)
    F = F[np.isfinite(F).all(axis=1)]
    F = F[(F < ref).all(axis=1)]
    return float(moocore.hypervolume(F, ref=ref)) if len(F) else 0.0


def evaluator_for(problem, config, source: str) -> Evaluator:
    """The evaluator of a run: one objective, or several with a multi-objective algorithm.

    A problem with several objectives needs an algorithm that reads vectors (``nsga2``,
    ``nsga3``, ``sms_emoa``), on any evaluation backend (workers return the vectors with their
    rows, :class:`VectorsToLedger` puts them in this process's ledger);
    anything else is a one-line :class:`~evoplan.errors.ConfigError`. An algorithm from an
    extra that is not installed is a one-line error here too, before any file is written.
    """
    from .config import REGISTRY
    from .errors import ConfigError
    from .extras import require

    algo_cls, _ = REGISTRY[config.algorithm.name]
    if getattr(algo_cls, "extra", None):
        require(*algo_cls.extra)
    multi = bool(getattr(algo_cls, "multi_objective", False))
    if problem.n_obj == 1:
        if multi:
            raise ConfigError(f"{source}: algorithm.name: {config.algorithm.name} is multi-objective but the "
                              "problem has one objective (give problem.params.objectives, or use ga, vega, ...)")
        return Evaluator(problem, config.problem.constraint_penalty)
    if not multi:
        multis = [k for k, (c, _) in REGISTRY.items() if getattr(c, "multi_objective", False)]
        raise ConfigError(f"{source}: algorithm.name: {config.algorithm.name} optimizes one objective and the "
                          f"problem has {problem.n_obj}: use {', '.join(multis)} (or weights, one objective)")
    return MultiEvaluator(problem, config.problem.constraint_penalty)


def add_hypervolume(history, algorithm):
    """``history`` with a ``hypervolume`` column when ``algorithm`` keeps one per generation."""
    values = getattr(algorithm, "hypervolumes", None)
    if values is not None:
        history = history.assign(hypervolume=np.asarray(values[: len(history)] + [np.nan] * (len(history) - len(values))))
    return history


def front_frame(problem, space, algorithm):
    """The archive as a table: decoded variables, objective values (``F`` as the problem
    returns them), Eq. 9 over them (``weighted_sum``), the raw criteria when the problem has
    ``criteria(X)``, and ``weighted_choice``: the point where the weighted sum is lowest."""
    import pandas as pd

    X, F = algorithm.front_X, algorithm.front_F
    order = np.lexsort(F.T[::-1]) if len(F) else np.zeros(0, dtype=int)
    X, F = X[order], F[order]
    names = objective_names(problem)
    frame = pd.DataFrame([space.named(x) for x in X], columns=space.names)
    for j, name in enumerate(names):
        frame[f"F_{name}"] = F[:, j]
    ws = F @ scalarization_weights(problem) if len(F) else np.zeros(0)
    frame["weighted_sum"] = ws
    frame["weighted_choice"] = np.arange(len(F)) == (np.argmin(ws) if len(F) else -1)
    criteria = getattr(problem, "criteria", None)
    if callable(criteria) and len(X):
        for key, values in criteria(X).items():
            values = np.asarray(values, dtype=float)
            if key not in frame and np.isfinite(values).any():
                frame[key] = values
    return frame


def write_front(prepared, algorithm, out) -> None:
    """``pareto.csv`` and (if plots are on) ``pareto.png`` of a multi-objective run."""
    if not hasattr(algorithm, "front_F"):
        return
    from .engine import write_atomic

    problem = prepared.evaluator.problem
    frame = front_frame(problem, prepared.space, algorithm)
    write_atomic(out / "pareto.csv", frame.to_csv(index=False).encode())
    if prepared.config.output.plot and len(frame):
        from .plots import pareto_png

        names = objective_names(problem)
        weights = dict(zip(names, scalarization_weights(problem)))
        title = f"{prepared.config.name}: {prepared.config.algorithm.name}, {len(frame)} non-dominated points"
        write_atomic(out / "pareto.png", pareto_png(frame, names, weights, title))
