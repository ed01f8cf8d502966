"""The evaluation cache of a run: genotype -> objective value, in bounded memory.

Evolutionary algorithms over a finite binary codec propose the same genotype again and again:
the GA's offspring repeat members of the population (crossover of two equal parents, an elite
copied over), VEGA's infections copy a host's own bits back into it. The engine looks every
genotype up here first and evaluates only those it has not seen, so a deterministic black box
is never asked twice for the same point.

**Counting** (``budget``): ``distinct`` (the default) charges the evaluation budget only for
genotypes actually evaluated, because the budget stands for the cost of the black box (a CAM
system, the toolpath engine), and a cache hit costs a dictionary look-up; comparing
algorithms "at equal evaluations" then means at an equal number of calls of the black box.
``all`` charges every genotype asked for, hits included: the count evoplan kept before the
cache (the run's numbers are then identical to a run without cache, only faster).

**Memory.** At most ``size`` genotypes are kept; when full, the oldest entry is dropped
(first in, first out). A dropped genotype asked for again is evaluated and charged again.
Failed evaluations (``inf``) are not stored: a crash may be transient, so it is retried.

**State as plain data.** The cache is a few numpy arrays (packed genotypes, values) and
integers (:meth:`to_data` / :meth:`from_data`); the look-up dictionary is rebuilt from them,
so a checkpoint stores data only.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

Budget = Literal["distinct", "all"]


class CacheConfig(BaseModel):
    """The ``cache`` group of a run or study file."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    size: int = Field(100_000, ge=0, description="genotypes kept (first in, first out); 0: no cache")
    budget: Budget = Field("distinct", description="what the evaluation budget counts: distinct genotypes or all asked")
    stall_generations: int = Field(
        100, ge=1, description="under budget: distinct, stop after this many generations without a new genotype"
    )


def pack(G: np.ndarray) -> np.ndarray:
    """Rows of ``G`` as byte rows ``(n, k) uint8``: 8 bits a byte for booleans, raw bytes otherwise."""
    G = np.ascontiguousarray(G)
    if G.dtype == bool:
        return np.packbits(G, axis=1)
    return np.ascontiguousarray(G.astype(np.float64)).view(np.uint8).reshape(len(G), -1)


class EvaluationCache:
    """A first-in-first-out table of at most ``size`` (packed genotype, objective value) pairs."""

    def __init__(self, size: int = 100_000, budget: Budget = "distinct", stall_generations: int = 100) -> None:
        self.size = int(size)
        self.budget = budget
        self.stall_generations = int(stall_generations)
        self.keys = np.zeros((0, 0), dtype=np.uint8)
        self.values = np.zeros(0)
        self.next = 0  # slot the next entry goes to (once the table is full: the oldest entry)
        self.hits = 0
        self.misses = 0
        self._index: dict[bytes, int] = {}

    @classmethod
    def from_config(cls, config: CacheConfig) -> "EvaluationCache":
        return cls(config.size, config.budget, config.stall_generations)

    @property
    def charge_hits(self) -> bool:
        return self.budget == "all"

    def __len__(self) -> int:
        return len(self._index)

    def lookup(self, G: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(keys, f, first)`` for a batch ``G``.

        ``f`` holds the stored value of every row already known (NaN elsewhere); ``first`` is
        the index of the first row of the batch with the same genotype (a row repeated inside
        one batch is evaluated once). Rows to evaluate: ``isnan(f) & (first == arange(n))``.
        """
        keys = pack(G)
        f = np.full(len(G), np.nan)
        first = np.arange(len(G))
        seen: dict[bytes, int] = {}
        for i, row in enumerate(keys):
            k = row.tobytes()
            slot = self._index.get(k)
            if slot is not None:
                f[i] = self.values[slot]
            elif k in seen:
                first[i] = seen[k]
            else:
                seen[k] = i
        return keys, f, first

    def store(self, keys: np.ndarray, f: np.ndarray) -> None:
        """Add the rows ``keys`` with finite values ``f`` (failures are not kept)."""
        if self.size == 0:
            return
        for row, value in zip(keys, f):
            if not np.isfinite(value):
                continue
            k = row.tobytes()
            if k in self._index:
                continue
            if self.values.size < self.size and self.next == self.values.size:
                self._grow(keys.shape[1])
            if len(self._index) >= self.size:  # full: drop the oldest entry, in this slot
                del self._index[self.keys[self.next].tobytes()]
            self.keys[self.next], self.values[self.next] = row, value
            self._index[k] = self.next
            self.next = (self.next + 1) % self.size

    def _grow(self, width: int) -> None:
        n = min(self.size, max(64, 2 * self.values.size))
        keys = np.zeros((n, width), dtype=np.uint8)
        values = np.full(n, np.nan)
        if self.values.size:
            keys[: self.values.size] = self.keys
            values[: self.values.size] = self.values
        self.keys, self.values = keys, values

    # -- plain data for checkpoints ------------------------------------------------------------
    def to_data(self) -> dict[str, Any]:
        """The whole cache as numpy arrays and integers (what a checkpoint stores)."""
        n = len(self._index)
        filled = np.arange(n) if n < self.size else np.arange(self.size)
        return {"size": self.size, "budget": self.budget, "stall_generations": self.stall_generations,
                "keys": self.keys[filled].copy(), "values": self.values[filled].copy(),
                "next": self.next, "hits": self.hits, "misses": self.misses}

    @classmethod
    def from_data(cls, data: dict[str, Any]) -> "EvaluationCache":
        cache = cls(int(data["size"]), str(data["budget"]), int(data["stall_generations"]))
        cache.values = np.asarray(data["values"], dtype=float)
        keys = np.asarray(data["keys"], dtype=np.uint8)
        cache.keys = keys.reshape(cache.values.size, -1) if cache.values.size else np.zeros((0, 0), np.uint8)
        cache.next, cache.hits, cache.misses = int(data["next"]), int(data["hits"]), int(data["misses"])
        cache._index = {row.tobytes(): i for i, row in enumerate(cache.keys)}
        return cache

    def __getstate__(self) -> dict[str, Any]:
        return self.to_data()

    def __setstate__(self, data: dict[str, Any]) -> None:
        self.__dict__.update(EvaluationCache.from_data(data).__dict__)
