"""The ask/tell contract every evoplan algorithm follows.

An algorithm owns its populations as numpy arrays and never evaluates anything itself:

- ``ask() -> G: (m, L) bool`` gives a batch of genotypes to evaluate;
- ``tell(f: (m,) float) -> bool`` takes their objective values (minimized; ``inf`` for a failed
  evaluation) and says whether a generation has just ended.

A generation may take several ask/tell rounds (VEGA: offspring, then infected hosts), so that
every evaluation is made, and counted, by the engine. Between generations the algorithm's
attributes, with the generator it holds, are the state a checkpoint stores (as data).
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np


class Algorithm(ABC):
    """Base class: a named algorithm over binary genotypes of ``n_bits`` bits."""

    name: str = "algorithm"

    def __init__(self, n_bits: int, rng: np.random.Generator) -> None:
        if n_bits < 1:
            raise ValueError("the genotype needs at least one bit")
        self.n_bits = int(n_bits)
        self.rng = rng
        self.generation = -1  # -1: the initial population is not evaluated yet
        self.G = np.zeros((0, self.n_bits), dtype=bool)
        self.f = np.zeros(0)

    @abstractmethod
    def ask(self) -> np.ndarray:
        """The next batch of genotypes to evaluate, ``(m, n_bits) bool``."""

    @abstractmethod
    def tell(self, f: np.ndarray) -> bool:
        """Objective values of the last batch; True when a generation has ended."""

    def state_dict(self) -> dict:
        """The algorithm's state as named values for a data-only checkpoint (:mod:`evoplan.checkpoint`).

        By default every attribute: arrays, numbers, strings, the generator (stored as its
        ``bit_generator.state``) and the settings model (not stored: rebuilt from the run
        file). An algorithm holding anything else (another library's objects) cannot be
        checkpointed as data; the checkpoint then says which attribute, and ``--resume`` refuses.
        """
        return dict(vars(self))

    def load_state_dict(self, values: dict) -> None:
        """Take back the values of :meth:`state_dict` (the generator already loaded in place)."""
        for name, value in values.items():
            setattr(self, name, value)

    @property
    def population(self) -> tuple[np.ndarray, np.ndarray]:
        """The current host population and its objective values, ``((N, L), (N,))``."""
        return self.G, self.f
