"""What every adapter shares: the unit-cube search space and the registry entry.

An adapter is an evoplan :class:`~evoplan.algorithms.base.Algorithm` (ask/tell over a batch)
that drives another library's algorithm. Because it follows the same contract, an adapted
algorithm runs inside :func:`evoplan.engine.run` exactly like the GA and VEGA: the engine
evaluates every batch it asks for, counts every row, keeps the best, records one history row
per generation and stops on the same :class:`~evoplan.engine.Termination`. That is how the
budget is counted the same way for every algorithm: no adapter calls the objective itself.

A real-valued algorithm searches the unit cube ``[0, 1]^d``; :class:`UnitCube` maps a row of it
to the problem's phenotype (reals on their bounds; integers and choices by equal-width bins,
the rule the binary codec uses). A binary algorithm searches the problem's own
:class:`~evoplan.space.Space` (the same Eq. 8 codec and bit counts as evoplan's GA).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict

from ..space import Space


class AdapterConfig(BaseModel):
    """Base of the adapters' settings (unknown keys rejected, like every evoplan config)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    representation: Literal["real", "binary"] = "real"


class UnitCube:
    """The search space of a real-valued adapter: ``U: (n, d)`` in ``[0, 1]`` -> ``X: (n, d)``.

    ``n_bits`` is the width of a search row (``d`` here), the name the engine and the
    :class:`~evoplan.algorithms.base.Algorithm` base class use for a genotype's width.
    """

    def __init__(self, space: Space) -> None:
        self.space = space
        self.n_bits = space.n_var

    def decode(self, U: np.ndarray) -> np.ndarray:
        """Phenotypes of unit-cube rows, ``(n, d) -> (n, d)``; values outside ``[0, 1]`` are clipped."""
        return self.space.from_unit(U)


def search_space(config, space: Space):
    """The space an algorithm with ``config`` searches: ``space`` itself, or its unit cube."""
    return UnitCube(space) if getattr(config, "representation", "binary") == "real" else space


def child_seed(rng: np.random.Generator) -> int:
    """A seed for another library's generator, drawn from the run's own generator."""
    return int(rng.integers(0, 2**31 - 1))
