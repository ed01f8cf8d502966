"""The run engine: ask -> evaluate -> tell -> record -> checkpoint, until a termination criterion.

The engine owns the counting: every genotype an algorithm asks for is looked up in the run's
:class:`~evoplan.cache.EvaluationCache` (if any) and, if new, decoded, evaluated and counted
(VEGA's infections included); ``cache.budget`` says whether a cache hit is charged too. The
best genotype ever evaluated is kept, with the trace of improvements at evaluation
granularity (``improvements``: the evaluation count and value of every new best). After each
generation it appends one history row and may write a checkpoint. The whole state lives in
:class:`RunState` (the algorithm with the generator it draws from, the counters, the cache,
the history), so a run resumed from a checkpoint continues with the very numbers an
uninterrupted run would have drawn.
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from . import __version__
from .algorithms.base import Algorithm
from .cache import EvaluationCache
from .evaluation import Evaluation, Evaluator
from .space import Space

HISTORY_COLUMNS = ("generation", "evaluations", "best", "mean", "worst", "std", "failures", "cache_hits", "seconds")
MAX_ERRORS_KEPT = 5


@dataclass(frozen=True)
class Termination:
    """Stop after ``generations``, ``evaluations``, reaching ``target``, or ``seconds`` of wall time.

    Checked after every generation; whichever criterion is met first stops the run. A
    generation is never cut in half, so the evaluation budget may be exceeded by less than
    one generation's evaluations (the count actually used is reported).
    """

    generations: int | None = None
    evaluations: int | None = None
    target: float | None = None
    seconds: float | None = None

    def reached(self, state: "RunState") -> str | None:
        if self.target is not None and state.best_f <= self.target:
            return "target"
        if self.generations is not None and state.algorithm.generation >= self.generations:
            return "generations"
        if self.evaluations is not None and state.evaluations >= self.evaluations:
            return "evaluations"
        if self.seconds is not None and state.elapsed >= self.seconds:
            return "seconds"
        if state.cache is not None and state.stalled >= state.cache.stall_generations:
            return "stalled"  # budget: distinct, and no new genotype for that many generations
        return None


@dataclass
class RunState:
    """Everything a run needs to continue: stored as data in a checkpoint (:mod:`evoplan.checkpoint`)."""

    algorithm: Algorithm
    rng: np.random.Generator
    evaluations: int = 0
    failures: int = 0
    best_f: float = np.inf
    best_g: np.ndarray | None = None
    history: list[tuple] = field(default_factory=list)
    elapsed: float = 0.0
    errors: list[str] = field(default_factory=list)
    stop_reason: str | None = None
    fingerprint: str = ""
    version: str = __version__
    cache: EvaluationCache | None = None
    cache_hits: int = 0  # genotypes answered by the cache (charged only under budget: all)
    stalled: int = 0  # consecutive generations without a charged evaluation
    improvements: list[tuple[int, float]] = field(default_factory=list)  # (evaluation, new best)

    def record(self) -> None:
        """Append the history row of the generation that just ended."""
        f = self.algorithm.f
        total = float(np.add.reduce(f))
        if not math.isfinite(total):
            f = f[np.isfinite(f)]
            total = float(np.add.reduce(f))
        if f.size:  # mean, max, std as numpy computes them (same sums, same bits), in fewer calls
            mean = total / f.size
            d = f - mean
            stats = (mean, float(np.maximum.reduce(f)), math.sqrt(float(np.add.reduce(d * d)) / f.size))
        else:
            stats = (math.nan, math.nan, math.nan)
        self.history.append(
            (self.algorithm.generation, self.evaluations, self.best_f, *stats,
             self.failures, self.cache_hits, round(self.elapsed, 6))
        )


class Checkpointer:
    """Writes the run state atomically every ``every_generations`` or ``every_seconds``.

    A checkpoint is written to a temporary file in the same folder, flushed to disk and renamed
    over the previous one, so a run killed at any instant (SIGKILL included) leaves either the
    old or the new checkpoint, never a torn one.
    """

    def __init__(self, path: str | Path, every_generations: int | None = None,
                 every_seconds: float | None = 30.0) -> None:
        self.path = Path(path)
        self.every_generations = every_generations
        self.every_seconds = every_seconds
        self._last_time = time.perf_counter()

    def due(self, generation: int) -> bool:
        if self.every_generations and generation % self.every_generations == 0:
            return True
        return bool(self.every_seconds) and time.perf_counter() - self._last_time >= self.every_seconds

    def save(self, state: RunState) -> None:
        from .checkpoint import dumps  # data only: JSON + arrays, never a pickle

        write_atomic(self.path, dumps(state))
        self._last_time = time.perf_counter()

    @staticmethod
    def load(path: str | Path, fresh: RunState) -> RunState:
        """The checkpoint at ``path`` loaded into ``fresh`` (a new state of the same run file).

        ``ValueError`` (a :class:`~evoplan.checkpoint.CheckpointError`) if the file is damaged
        (checksum), of another version or configuration, or of an algorithm that is not data.
        """
        from .checkpoint import CheckpointError, load_into, read

        meta, arrays = read(path)
        if meta.get("fingerprint") != fresh.fingerprint:
            raise CheckpointError("made by another configuration")
        return load_into(meta, arrays, fresh)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_atomic(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` completely or not at all (temp file, fsync, rename)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, 0o666 & ~_umask())  # mkstemp makes 0600; a results file follows the umask
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def run(
    state: RunState,
    space: Space,
    evaluator: Evaluator,
    termination: Termination,
    checkpointer: Checkpointer | None = None,
    on_generation: Callable[[RunState], None] | None = None,
) -> RunState:
    """Run (or continue) the algorithm in ``state`` until ``termination``; returns the state."""
    algo = state.algorithm
    clock0 = time.perf_counter() - state.elapsed
    charged_before = state.evaluations
    while not (state.history and (reason := termination.reached(state))):
        G = algo.ask()
        f = evaluate(state, G, space, evaluator)
        if algo.tell(f):
            state.stalled = 0 if state.evaluations > charged_before else state.stalled + 1
            charged_before = state.evaluations
            state.elapsed = time.perf_counter() - clock0
            state.record()
            if on_generation is not None:
                on_generation(state)
            if checkpointer is not None and checkpointer.due(algo.generation):
                checkpointer.save(state)
    state.stop_reason = reason
    if checkpointer is not None:
        checkpointer.save(state)
    return state


@dataclass
class Pending:
    """A batch looked up in the cache: the values known (NaN: not yet), and the rows to evaluate.

    ``todo``: the first occurrence of each genotype the cache does not hold; ``first``: the
    index of each row's first occurrence in the batch (a repeat takes its value).
    """

    G: np.ndarray
    keys: np.ndarray | None
    f: np.ndarray
    first: np.ndarray
    todo: np.ndarray


def lookup(state: RunState, G: np.ndarray) -> Pending:
    """The rows of ``G`` the run's cache answers, and those left to evaluate (:class:`Pending`)."""
    n = len(G)
    cache = state.cache
    if cache is None:
        return Pending(G, None, np.full(n, np.nan), np.arange(n), np.arange(n))
    return Pending(G, *cache.pending(G))


def settle(state: RunState, pending: Pending, result: Evaluation | None) -> np.ndarray:
    """The batch's values once ``result`` (the evaluation of ``pending.todo``) is in: stored in
    the cache, failures, hits and charged evaluations counted, the best and its improvements kept.

    Rows are charged in batch order, so the k-th charged row is evaluation ``k`` of the run:
    the index ``improvements`` records (first-hit runtimes at evaluation granularity). A row
    charges what its evaluation says it cost (``Evaluation.cost``: a screened toolpath plan 0,
    a simulated one 1, so the budget counts simulations), else 1.
    """
    G, keys, f, first, todo = pending.G, pending.keys, pending.f, pending.first, pending.todo
    n = len(G)
    cache = state.cache
    if todo.size:
        f[todo] = result.f
        if result.failed.any():
            _count_failures(state, result)
        if cache is not None:
            cache.store(keys if todo.size == n else keys[todo], result.f, fresh=True)
    if todo.size < n:  # a row repeated inside the batch takes its first occurrence's value
        repeat = np.isnan(f)
        f[repeat] = f[first[repeat]]
    hits = n - todo.size
    charge_hits = cache is not None and cache.charge_hits
    if cache is not None:
        cache.hits += hits
        cache.misses += todo.size
        state.cache_hits += hits
    costed = not charge_hits and result is not None and result.cost is not None
    total = n if charge_hits else (int(result.cost.astype(np.int64).sum()) if costed else todo.size)
    if n and np.minimum.reduce(f) < state.best_f:  # improvements: the evaluation number of each
        _record_improvements(state, f, todo, charge_hits, result.cost if costed else None)
        i = int(np.argmin(f))
        state.best_f, state.best_g = float(f[i]), G[i].copy()
    state.evaluations += total
    return f


def _record_improvements(state: RunState, f: np.ndarray, todo: np.ndarray, charge_hits: bool,
                         cost: np.ndarray | None) -> None:
    """Append ``(evaluation number, value)`` for each row of the batch ``f`` below every value
    before it (the run's best included). Row ``i`` is evaluation ``evaluations + the cost
    charged for rows 0..i``: every row costs 1 when hits are charged, else the rows ``todo``
    (ascending) cost ``cost`` each (1 where None). Only the rows under the run's best are
    visited: a few, where a running minimum over the batch would cost a pass of its own."""
    candidates = np.flatnonzero(f < state.best_f)
    if charge_hits:
        index = state.evaluations + candidates + 1
    else:
        charged = np.cumsum(cost.astype(np.int64)) if cost is not None else np.arange(1, todo.size + 1)
        before = np.searchsorted(todo, candidates, side="right")  # charged rows up to each
        index = state.evaluations + np.where(before > 0, charged[np.maximum(before - 1, 0)], 0)
    best = state.best_f
    for i, k in zip(candidates.tolist(), index.tolist()):
        if f[i] < best:
            best = float(f[i])
            state.improvements.append((int(k), best))


def evaluate(state: RunState, G: np.ndarray, space: Space, evaluator: Evaluator) -> np.ndarray:
    """Objective values of the batch ``G``: cached ones looked up, new ones evaluated and counted."""
    pending = lookup(state, G)
    todo = pending.todo
    if not todo.size:
        return settle(state, pending, None)
    return settle(state, pending, evaluator(space.decode(G if todo.size == len(G) else G[todo])))


def _count_failures(state: RunState, result: Evaluation) -> None:
    """Count the failures of a batch that has some and keep the first few distinct messages."""
    state.failures += int(result.failed.sum())
    for message in dict.fromkeys(result.errors):  # distinct messages, the first few
        if message not in state.errors and len(state.errors) < MAX_ERRORS_KEPT:
            state.errors.append(message)
