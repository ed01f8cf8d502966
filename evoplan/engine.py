"""The run engine: ask -> evaluate -> tell -> record -> checkpoint, until a termination criterion.

The engine owns the counting: every genotype an algorithm asks for is decoded, evaluated and
counted (the re-evaluation of infected hosts included), and the best genotype ever evaluated
is kept. After each generation it appends one history row and may write a checkpoint. The
whole state lives in :class:`RunState` (the algorithm with the generator it draws from, the
counters, the history), so a run resumed from a checkpoint continues with the very numbers an
uninterrupted run would have drawn.
"""

from __future__ import annotations

import os
import pickle
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from . import __version__
from .algorithms.base import Algorithm
from .evaluation import Evaluator
from .space import Space

HISTORY_COLUMNS = ("generation", "evaluations", "best", "mean", "worst", "std", "failures", "seconds")
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
        return None


@dataclass
class RunState:
    """Everything a run needs to continue: pickled whole into a checkpoint."""

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

    def record(self) -> None:
        """Append the history row of the generation that just ended."""
        f = self.algorithm.f
        if not np.isfinite(f).all():
            f = f[np.isfinite(f)]
        stats = (f.mean(), f.max(), f.std()) if f.size else (np.nan, np.nan, np.nan)
        self.history.append(
            (self.algorithm.generation, self.evaluations, self.best_f, *map(float, stats),
             self.failures, round(self.elapsed, 6))
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
        write_atomic(self.path, pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL))
        self._last_time = time.perf_counter()

    @staticmethod
    def load(path: str | Path) -> RunState:
        with open(path, "rb") as fh:
            state = pickle.load(fh)
        if not isinstance(state, RunState):
            raise ValueError(f"{path}: not an evoplan checkpoint")
        if state.version != __version__:
            raise ValueError(f"{path}: checkpoint of evoplan {state.version}, this is {__version__}")
        return state


def write_atomic(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` completely or not at all (temp file, fsync, rename)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
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
    while not (state.history and (reason := termination.reached(state))):
        G = algo.ask()
        result = evaluator(space.decode(G))
        state.evaluations += len(G)
        if result.failed.any():
            state.failures += int(result.failed.sum())
            for message in dict.fromkeys(result.errors):  # distinct messages, the first few
                if message not in state.errors and len(state.errors) < MAX_ERRORS_KEPT:
                    state.errors.append(message)
        i = int(np.argmin(result.f))
        if result.f[i] < state.best_f:
            state.best_f, state.best_g = float(result.f[i]), G[i].copy()
        if algo.tell(result.f):
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
