"""The ask/tell contract every evoplan algorithm follows.

An algorithm owns its populations as numpy arrays and never evaluates anything itself:

- ``ask() -> G: (m, L) bool`` gives a batch of genotypes to evaluate;
- ``tell(f: (m,) float) -> bool`` takes their objective values (minimized; ``inf`` for a failed
  evaluation) and says whether a generation has just ended.

A generation may take several ask/tell rounds (VEGA: offspring, then infected hosts), so that
every evaluation is made, and counted, by the engine. Between generations the whole algorithm
object, with the generator it holds, is the state a checkpoint stores.
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

    @property
    def population(self) -> tuple[np.ndarray, np.ndarray]:
        """The current host population and its objective values, ``((N, L), (N,))``."""
        return self.G, self.f
