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

**Vectorized.** A genotype is packed into one fixed-width key (up to 48 bits: an exact
integer code; up to 64 bits: one ``uint64``; wider: one ``np.void`` of its bytes). Keys of up
to 64 bits live in a compiled open-addressing table (:mod:`evoplan.key_index`) once it pays
(:mod:`evoplan.compiled`: numba loaded, or enough rows put through): a batch of boolean
genotypes is coded, looked up and its repeats found in one compiled pass, and stored in
another; no Python object per row. Until then, and for wider keys, the index is a dictionary
(Python ints, or ``bytes``), one C-level pass a batch; the table takes over its entries. Profile (pyinstrument, Kubota, GA pop 2000 x 40, ten runs, old and new code in one
sitting): with a dictionary of Python ints the cache held 0.76 of 1.79 s (look-up 0.47, store
0.29); with the compiled table 0.15 of 0.82 s (look-up 0.11, store 0.03).
``runs/bench/floor.py`` times it against a plain numpy GA.

**State as plain data.** The cache is a few numpy arrays (packed genotypes as byte rows,
values) and integers (:meth:`to_data` / :meth:`from_data`); the index is rebuilt from
them, so a checkpoint stores data only.
"""

from __future__ import annotations

from collections import deque
from itertools import repeat
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from .compiled import use_compiled

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


CODE_BYTES = 6  # genotypes of up to 48 bits are keyed by an exact integer code
RESERVE_SLOTS = 1 << 17  # slots a cache reserves at its first store (2 MB of codes and values)


def key_dtype(width: int) -> np.dtype:
    """The dtype of the key of a ``width``-byte packed genotype: an ``int64`` code up to
    :data:`CODE_BYTES`, one ``uint64`` up to 8 bytes, else the bytes (``V<width>``)."""
    if width <= CODE_BYTES:
        return np.dtype(np.int64)
    return np.dtype(np.uint64) if width <= 8 else np.dtype(f"V{width}")


def genotype_codes(G: np.ndarray) -> np.ndarray:
    """Exact ``int64`` codes ``sum_j G[:, j] 2 ** j`` of boolean genotypes of at most 48 bits
    (distinct genotypes, distinct integers below ``2 ** 48``)."""
    return (G @ np.ldexp(1.0, np.arange(G.shape[1]))).astype(np.int64)


def to_keys(rows: np.ndarray) -> np.ndarray:
    """Byte rows ``(n, k) uint8`` -> one key each, ``(n,)`` of :func:`key_dtype` ``(k)``."""
    n, k = rows.shape
    if k <= CODE_BYTES:
        return genotype_codes(np.unpackbits(rows, axis=1).astype(bool))
    if k <= 8:
        padded = np.zeros((n, 8), dtype=np.uint8)
        padded[:, :k] = rows
        return padded.view(np.uint64).ravel()
    return np.ascontiguousarray(rows).view(key_dtype(k)).ravel()


def to_rows(keys: np.ndarray, width: int) -> np.ndarray:
    """The inverse of :func:`to_keys`: ``(n,)`` keys -> ``(n, width) uint8`` byte rows."""
    if keys.size == 0:
        return np.zeros((0, width), dtype=np.uint8)
    if width <= CODE_BYTES:
        shifts = np.arange(8 * width, dtype=np.uint64)
        bits = (keys.astype(np.uint64)[:, None] >> shifts) & np.uint64(1)
        return np.packbits(bits.astype(bool), axis=1)
    rows = np.ascontiguousarray(keys).view(np.uint8).reshape(len(keys), -1)
    return rows[:, :width].copy()


def index_keys(keys: np.ndarray):
    """What the index is keyed by: ``int64`` for keys of at most 8 bytes (a code as it is, a
    ``uint64`` reinterpreted), else the keys' bytes as a Python list."""
    if keys.dtype == np.int64:
        return keys
    if keys.dtype == np.uint64:
        return keys.view(np.int64)
    return keys.tolist()


def first_occurrence(keys) -> np.ndarray:
    """For each key, the index of its first occurrence in ``keys``: an ``int64`` array by one
    sort (``np.unique``), a list of hashable keys by one dict pass."""
    if isinstance(keys, np.ndarray):
        _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
        return first[inverse]
    n = len(keys)
    seen = dict(zip(reversed(keys), range(n - 1, -1, -1)))  # the earliest index is written last
    return np.fromiter(map(seen.__getitem__, keys), dtype=np.intp, count=n)


class DictIndex:
    """Key -> slot in a dictionary, one C-level pass per batch; the interface of
    :class:`evoplan.key_index.KeyIndex`. Keys are ``bytes`` (a list: genotypes wider than 8
    bytes) or ``int64`` keys (an array, held as Python ints until the compiled table pays)."""

    def __init__(self) -> None:
        self._dict: dict = {}

    def __len__(self) -> int:
        return len(self._dict)

    def items(self) -> tuple[np.ndarray, np.ndarray]:
        """``(keys, slots)`` of ``int64`` entries (for the compiled table taking them over)."""
        n = len(self._dict)
        return (np.fromiter(self._dict.keys(), dtype=np.int64, count=n),
                np.fromiter(self._dict.values(), dtype=np.int64, count=n))

    def get(self, keys) -> np.ndarray:
        keys = _python(keys)
        return np.fromiter(map(self._dict.get, keys, repeat(-1)), dtype=np.intp, count=len(keys))

    def lookup(self, keys) -> tuple[np.ndarray, np.ndarray]:
        n = len(keys)
        slot = self.get(keys) if self._dict else np.full(n, -1)
        first = np.arange(n)
        miss = np.flatnonzero(slot < 0)
        if miss.size > 1:
            missed = keys[miss] if isinstance(keys, np.ndarray) else [keys[i] for i in miss]
            first[miss] = miss[first_occurrence(missed)]
        return slot, first

    def lookup_rows(self, G: np.ndarray, exponents: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(codes, slot, first)`` of boolean rows keyed by ``sum_j G[i, j] 2 ** exponents[j]``."""
        codes = (G @ np.ldexp(1.0, exponents)).astype(np.int64)
        return (codes, *self.lookup(codes))

    def update(self, keys, slots: np.ndarray) -> None:
        self._dict.update(zip(_python(keys), slots.tolist()))

    def remove(self, keys) -> None:
        deque(map(self._dict.pop, _python(keys)), maxlen=0)


def _python(keys):
    """An ``int64`` key array as a list of Python ints (a list of ``bytes`` as it is)."""
    return keys.tolist() if isinstance(keys, np.ndarray) else keys


def new_index(width: int, expected: int = 0, rows: int = 0):
    """The index for keys of ``width`` bytes (``expected`` of them, likely), before a batch
    of ``rows``: the compiled table for up to 8 bytes once it pays (:func:`use_compiled`),
    else a dictionary."""
    if width <= 8 and use_compiled(rows):
        from .key_index import KeyIndex  # numba: imported only when it pays

        return KeyIndex(expected)
    return DictIndex()


class EvaluationCache:
    """A first-in-first-out table of at most ``size`` (packed genotype, objective value) pairs."""

    def __init__(self, size: int = 100_000, budget: Budget = "distinct", stall_generations: int = 100,
                 expected: int | None = None) -> None:
        self.size = int(size)
        # the entries a run will likely store (its budget): the key index starts at that size,
        # not at ``size``, so a short run neither clears nor pages in a table it cannot fill;
        # a run that stores more grows it (it changes time, never numbers)
        self.expected = self.size if expected is None else min(self.size, max(int(expected), 0))
        self.budget = budget
        self.stall_generations = int(stall_generations)
        self.width = 0  # bytes of a packed genotype (set by the first batch)
        self.codes = np.zeros(0, dtype=np.uint64)  # key of each slot, slot order
        self.values = np.zeros(0)  # value of each slot
        self.next = 0  # slot the next entry goes to (once the table is full: the oldest entry)
        self.hits = 0
        self.misses = 0
        self._index = DictIndex()  # key -> slot (replaced by the first batch's :func:`new_index`)
        self._exponents = np.zeros(0, dtype=np.int64)  # locus j of a coded genotype weighs 2 ** j

    @classmethod
    def from_config(cls, config: CacheConfig, expected: int | None = None) -> "EvaluationCache":
        return cls(config.size, config.budget, config.stall_generations, expected)

    @property
    def charge_hits(self) -> bool:
        return self.budget == "all"

    def __len__(self) -> int:
        return len(self._index)

    @property
    def keys(self) -> np.ndarray:
        """The packed genotypes of the slots in use, ``(len, width) uint8``."""
        return to_rows(self.codes[: len(self._index)], self.width)

    def lookup(self, G: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(keys, f, first)`` for a batch ``G``.

        ``keys: (n,)`` the packed key of each row; ``f`` holds the stored value of every row
        already known (NaN elsewhere); ``first`` is the index of the first row of the batch
        with the same genotype (a row repeated inside one batch is evaluated once; a known
        row is its own first). Rows to evaluate: ``isnan(f) & (first == arange(n))``.
        """
        coded = G.dtype == bool and G.ndim == 2 and 0 < G.shape[1] <= 8 * CODE_BYTES
        if not self.width:
            self.width = -(-G.shape[1] // 8) if coded else pack(G[:1]).shape[1]
            self.codes = np.zeros(0, dtype=key_dtype(self.width))
            self._index = new_index(self.width, self.expected, len(G))
        elif self.width <= 8 and isinstance(self._index, DictIndex) and use_compiled(len(G)):
            self._index = _compiled_from(self._index, self.size)
        if coded:  # codes computed and looked up in one compiled pass
            if self._exponents.size != G.shape[1]:
                self._exponents = np.arange(G.shape[1])
            keys, slot, first = self._index.lookup_rows(np.ascontiguousarray(G), self._exponents)
        else:
            keys = to_keys(pack(G))
            slot, first = self._index.lookup(index_keys(keys))
        f = np.full(len(keys), np.nan)
        known = slot >= 0
        f[known] = self.values[slot[known]]
        return keys, f, first

    def pending(self, G: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`lookup` and the rows left to evaluate, ``isnan(f) & (first == arange(n))``:
        ``(keys, f, first, todo)``, in one compiled pass where the compiled table serves."""
        if (self.width and G.dtype == bool and G.ndim == 2 and G.shape[1] == self._exponents.size
                and hasattr(self._index, "pending_rows")):
            return self._index.pending_rows(np.ascontiguousarray(G), self._exponents, self.values)
        keys, f, first = self.lookup(G)
        return keys, f, first, np.flatnonzero(np.isnan(f) & (first == np.arange(len(f))))

    def store(self, keys: np.ndarray, f: np.ndarray, fresh: bool = False) -> None:
        """Add the keys ``keys`` (from :meth:`lookup`) with values ``f``, in order.

        Failures (non-finite values), keys already stored and repeats of an earlier key of the
        batch are skipped (``fresh``: the caller knows the keys are new and distinct, as the
        engine does for the rows a look-up left to evaluate). When full, each new entry takes
        the slot of the oldest one."""
        if self.size == 0 or keys.size == 0:
            return
        f = np.asarray(f, dtype=float)
        if fresh and keys.size <= self.size and hasattr(self._index, "store_fresh"):
            self._reserve(min(self.size, len(self._index) + keys.size))
            self.next = self._index.store_fresh(
                _as_int64(self.codes), self.values, _as_int64(keys), f, self.next, self.size)
            return
        keep = np.isfinite(f)
        if not fresh:
            slot, first = self._index.lookup(index_keys(keys))
            keep &= (first == np.arange(keys.size)) & (slot < 0)
        if not keep.all():
            keys, f = keys[keep], f[keep]
        if keys.size > self.size:  # only the last `size` survive the batch
            self.next = (self.next + keys.size - self.size) % self.size
            keys, f = keys[-self.size:], f[-self.size:]
        m = keys.size
        if m == 0:
            return
        filled = len(self._index)
        slots = (self.next + np.arange(m)) % self.size
        self._reserve(min(self.size, filled + m))
        old = slots[slots < filled]  # occupied slots: their entries are dropped
        if old.size:
            self._index.remove(index_keys(self.codes[old]))
        self.codes[slots], self.values[slots] = keys, f
        self._index.update(index_keys(keys), slots)
        self.next = int((self.next + m) % self.size)

    def _reserve(self, n: int) -> None:
        """Room for ``n`` slots: at once for up to :data:`RESERVE_SLOTS` (the memory is taken
        page by page as slots fill, and nothing is copied as a run's cache grows), then by
        doubling, up to ``size``. A slot not in use holds no value (``values`` is not read there)."""
        if n <= self.values.size:
            return
        cap = min(self.size, max(RESERVE_SLOTS, 2 * self.values.size, n))
        codes = np.zeros(cap, dtype=self.codes.dtype)
        values = np.empty(cap)
        codes[: self.values.size], values[: self.values.size] = self.codes, self.values
        self.codes, self.values = codes, values

    # -- plain data for checkpoints ------------------------------------------------------------
    def to_data(self) -> dict[str, Any]:
        """The whole cache as numpy arrays and integers (what a checkpoint stores)."""
        n = len(self._index)
        return {"size": self.size, "budget": self.budget, "stall_generations": self.stall_generations,
                "keys": self.keys, "values": self.values[:n].copy(),
                "next": self.next, "hits": self.hits, "misses": self.misses}

    @classmethod
    def from_data(cls, data: dict[str, Any]) -> "EvaluationCache":
        cache = cls(int(data["size"]), str(data["budget"]), int(data["stall_generations"]))
        values = np.asarray(data["values"], dtype=float)
        rows = np.asarray(data["keys"], dtype=np.uint8)
        cache.next, cache.hits, cache.misses = int(data["next"]), int(data["hits"]), int(data["misses"])
        if values.size:
            rows = rows.reshape(values.size, -1)
            cache.width = rows.shape[1]
            cache.codes, cache.values = to_keys(rows), values.copy()
            cache._index = new_index(cache.width, cache.size, values.size)
            cache._index.update(index_keys(cache.codes), np.arange(values.size))
        return cache

    def __getstate__(self) -> dict[str, Any]:
        return self.to_data()

    def __setstate__(self, data: dict[str, Any]) -> None:
        self.__dict__.update(EvaluationCache.from_data(data).__dict__)


def _as_int64(keys: np.ndarray) -> np.ndarray:
    """``int64`` or ``uint64`` keys as ``int64`` (a view: what the compiled table holds)."""
    return keys if keys.dtype == np.int64 else keys.view(np.int64)


def _compiled_from(index: DictIndex, expected: int):
    """The compiled table holding a dictionary index's ``int64`` entries."""
    from .key_index import KeyIndex

    table = KeyIndex(expected)
    table.update(*index.items())
    return table
