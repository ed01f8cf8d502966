"""What the Python API does after each generation: pymoo's ``verbose``, ``save_history`` and
``callback``, in pymoo's order (display, then history, then the callback: pymoo's
``Algorithm._post_advance``).

- ``verbose``: one line per generation on stdout, in pymoo's columns and number format
  (:class:`pymoo.util.display.column.Column`): ``n_gen`` counted as pymoo counts (the initial
  population is generation 1), ``n_eval``, the population's mean ``f_avg`` and the best value
  so far ``f_min``, both as the engine ranks them (penalized on a constrained problem, where
  pymoo shows ``cv_min``/``cv_avg`` and the feasible points' values instead).
- ``save_history``: a :class:`Population` per generation: the decoded population and its
  values (a copy of two arrays, where pymoo deep-copies the whole algorithm).
- ``callback``: called with the run's :class:`~evoplan.engine.RunState` (``state.algorithm``
  with its population ``G``, ``f`` and ``generation``, ``state.evaluations``, ``state.best_f``...).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class Population:
    """One generation as ``save_history`` keeps it: ``X`` decoded rows ``(N, n_var)``, ``F``
    their values ``(N,)``; ``n_gen`` counted as pymoo counts, ``n_eval`` evaluations so far."""

    n_gen: int
    n_eval: int
    X: np.ndarray
    F: np.ndarray


class ProgressLines:
    """pymoo's progress table: a header, then one line per generation."""

    def __init__(self, stream=None) -> None:
        from pymoo.util.display.column import Column

        self.stream = stream
        self.columns = [Column("n_gen", width=6), Column("n_eval", width=8), Column("f_avg"), Column("f_min")]
        self.started = False

    def __call__(self, n_gen: int, n_eval: int, f: np.ndarray, best: float) -> None:
        finite = f[np.isfinite(f)]
        values = (n_gen, n_eval, float(finite.mean()) if finite.size else None, best if np.isfinite(best) else None)
        for column, value in zip(self.columns, values):
            column.set(value)
        stream = self.stream or sys.stdout
        if not self.started:
            header = " | ".join(c.header() for c in self.columns)
            print("=" * len(header), header, "=" * len(header), sep="\n", file=stream)
            self.started = True
        print(" | ".join(c.text() for c in self.columns), file=stream)


class GenerationHooks:
    """The ``on_generation`` function of :func:`evoplan.engine.run` for the API's options.

    ``decode`` turns the algorithm's rows into phenotypes (the run's search space).
    """

    def __init__(self, decode: Callable[[np.ndarray], np.ndarray], callback=None, verbose: bool = False,
                 save_history: bool = False, stream=None) -> None:
        if callback is not None and not callable(callback):
            raise TypeError(f"callback must be callable (got {type(callback).__name__})")
        self.decode = decode
        self.callback = callback
        self.lines = ProgressLines(stream) if verbose else None
        self.populations: list[Population] | None = [] if save_history else None

    def __bool__(self) -> bool:
        return bool(self.callback or self.lines or self.populations is not None)

    def __call__(self, state) -> None:
        algo = state.algorithm
        n_gen = algo.generation + 1
        if self.lines is not None:
            self.lines(n_gen, state.evaluations, np.asarray(algo.f, dtype=float), state.best_f)
        if self.populations is not None:
            self.populations.append(Population(n_gen, state.evaluations, np.array(self.decode(algo.G), dtype=float),
                                               np.array(algo.f, dtype=float)))
        if self.callback is not None:
            self.callback(state)
