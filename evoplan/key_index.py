"""A compiled hash index of 64-bit keys -> slot numbers, the evaluation cache's look-up table.

Open addressing with linear probing over a power-of-two table kept at most half full; a key's
home is its Fibonacci hash (the key times 2**64 / golden ratio, top bits). Deletion shifts the
following entries of the probe run back (no tombstones), so a look-up never probes further
than the run it falls in. Every batch operation is one compiled pass (numba): no Python
object per row, which is what a ``dict`` of Python ints costs.

:meth:`KeyIndex.lookup` does in one pass what the cache needs of a batch: each key's slot (-1
when absent) and, for the absent ones, the index of the key's first occurrence in the batch
(a scratch table of the batch's own absent keys).
"""

from __future__ import annotations

import numba
import numpy as np

EMPTY = -1  # a look-up's answer for an absent key
FREE = 0  # a free table cell: cells hold slot + 1, so a new table is zeros (no pages written)
FIB = np.uint64(0x9E3779B97F4A7C15)
MIN_BITS = 10
MAX_START = 1 << 17  # entries a table is sized for at its start, at most (4 MB)


@numba.njit(cache=True, inline="always")
def _home(key, shift):
    return np.int64((np.uint64(key) * FIB) >> shift)


@numba.njit(cache=True)
def _position(tkeys, tslots, shift, key):
    """The table index holding ``key``, else the empty one ending its probe run."""
    mask = tkeys.size - 1
    i = _home(key, shift)
    while tslots[i] != FREE and tkeys[i] != key:
        i = (i + 1) & mask
    return i


@numba.njit(cache=True)
def _find(tkeys, tslots, shift, key):
    return tslots[_position(tkeys, tslots, shift, key)] - 1  # EMPTY where absent


@numba.njit(cache=True)
def _put(tkeys, tslots, shift, key, slot):
    """Set ``key -> slot``; True if the key was new."""
    i = _position(tkeys, tslots, shift, key)
    new = tslots[i] == FREE
    tkeys[i], tslots[i] = key, slot + 1
    return new


@numba.njit(cache=True)
def _remove(tkeys, tslots, shift, key):
    """Delete ``key`` (backward-shift deletion); True if it was present."""
    mask = tkeys.size - 1
    i = _position(tkeys, tslots, shift, key)
    if tslots[i] == FREE:
        return False
    j = i
    while True:  # close the gap at i with the next entry of the run that may move into it
        j = (j + 1) & mask
        if tslots[j] == FREE:
            break
        home = _home(tkeys[j], shift)
        if ((j - home) & mask) >= ((j - i) & mask):  # i lies on j's probe path: move j to i
            tkeys[i], tslots[i] = tkeys[j], tslots[j]
            i = j
    tslots[i] = FREE
    return True


@numba.njit(cache=True)
def _get_batch(tkeys, tslots, shift, keys):
    out = np.empty(keys.size, dtype=np.int64)
    for k in range(keys.size):
        out[k] = _find(tkeys, tslots, shift, keys[k])
    return out


@numba.njit(cache=True)
def _put_batch(tkeys, tslots, shift, keys, slots):
    added = 0
    for k in range(keys.size):
        added += _put(tkeys, tslots, shift, keys[k], slots[k])
    return added


@numba.njit(cache=True)
def _remove_batch(tkeys, tslots, shift, keys):
    removed = 0
    for k in range(keys.size):
        removed += _remove(tkeys, tslots, shift, keys[k])
    return removed


@numba.njit(cache=True)
def _lookup_batch(tkeys, tslots, shift, keys):
    n = keys.size
    slot = np.empty(n, dtype=np.int64)
    first = np.arange(n)
    bits = MIN_BITS
    while (1 << bits) < 2 * n:
        bits += 1
    skeys = np.empty(1 << bits, dtype=np.int64)
    sfirst = np.zeros(1 << bits, dtype=np.int64)
    sshift = np.uint64(64 - bits)
    for k in range(n):
        slot[k] = _find(tkeys, tslots, shift, keys[k])
        if slot[k] == EMPTY:
            seen = _find(skeys, sfirst, sshift, keys[k])
            if seen == EMPTY:
                _put(skeys, sfirst, sshift, keys[k], k)
            else:
                first[k] = seen
    return slot, first


@numba.njit(cache=True)
def _row_codes(G, exponents):
    """``G: (n, L) uint8`` of 0/1 -> ``(n,) int64`` codes ``sum_j G[i, j] << exponents[j]``."""
    n, L = G.shape
    codes = np.zeros(n, dtype=np.int64)
    for i in range(n):
        c = np.int64(0)
        for j in range(L):
            c |= np.int64(G[i, j]) << exponents[j]  # branch-free: the bits are random
        codes[i] = c
    return codes


@numba.njit(cache=True)
def _lookup_rows(tkeys, tslots, shift, G, exponents):
    codes = _row_codes(G, exponents)
    slot, first = _lookup_batch(tkeys, tslots, shift, codes)
    return codes, slot, first


@numba.njit(cache=True)
def _pending_rows(tkeys, tslots, shift, G, exponents, values):
    """:func:`_lookup_rows` with the known values ``values[slot]`` (NaN where absent) and the
    rows left to evaluate (absent first occurrences), in the same pass."""
    codes, slot, first = _lookup_rows(tkeys, tslots, shift, G, exponents)
    n = codes.size
    f = np.empty(n)
    todo = np.empty(n, dtype=np.int64)
    t = 0
    for k in range(n):
        if slot[k] != EMPTY:
            f[k] = values[slot[k]]
        else:
            f[k] = np.nan
            if first[k] == k:
                todo[t] = k
                t += 1
    return codes, f, first, todo[:t]


@numba.njit(cache=True)
def _store_fresh(tkeys, tslots, shift, codes, values, keys, f, start, filled, size):
    """Store the new, distinct ``keys`` with finite values ``f`` in the ring of slots
    ``codes, values`` from slot ``start`` on, each dropping the entry of a slot below
    ``filled`` (in use) first; returns ``(next slot, change in the entry count)``."""
    nxt, change = start, 0
    for k in range(keys.size):
        if not np.isfinite(f[k]):
            continue
        if nxt < filled:
            change -= _remove(tkeys, tslots, shift, codes[nxt])
        codes[nxt], values[nxt] = keys[k], f[k]
        change += _put(tkeys, tslots, shift, keys[k], nxt)
        nxt = (nxt + 1) % size
    return nxt, change


@numba.njit(cache=True)
def _rehash(keys, slots, tkeys, tslots, shift):
    """Insert the used cells of ``(keys, slots)`` (slot + 1, FREE where unused) into the empty
    table ``(tkeys, tslots)``."""
    for k in range(keys.size):
        if slots[k] != FREE:
            _put(tkeys, tslots, shift, keys[k], slots[k] - 1)


class KeyIndex:
    """``int64`` key -> slot (``int64 >= 0``), for batches of keys; grows as it fills.

    ``expected``: the entries it will likely hold (a cache's size): the table starts large
    enough for them, up to :data:`MAX_START` entries, so a run's cache is rarely rehashed."""

    def __init__(self, expected: int = 0) -> None:
        self._alloc(_bits_for(min(int(expected), MAX_START)))
        self.count = 0

    def _alloc(self, bits: int) -> None:
        self.bits = bits
        self.keys = np.zeros(1 << bits, dtype=np.int64)
        self.slots = np.zeros(1 << bits, dtype=np.int64)  # (FREE)
        self.shift = np.uint64(64 - bits)

    def __len__(self) -> int:
        return self.count

    def get(self, keys: np.ndarray) -> np.ndarray:
        """The slot of each key, -1 where absent."""
        return _get_batch(self.keys, self.slots, self.shift, keys)

    def lookup(self, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(slot, first)``: each key's slot (-1 where absent) and, for an absent key, the index
        of its first occurrence in ``keys`` (a present key, and a first occurrence: its own)."""
        return _lookup_batch(self.keys, self.slots, self.shift, keys)

    def lookup_rows(self, G: np.ndarray, exponents: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(codes, slot, first)`` of boolean rows ``G: (n, L)`` keyed by their codes
        ``sum_j G[i, j] 2 ** exponents[j]`` (``exponents`` distinct, below 63): one pass."""
        return _lookup_rows(self.keys, self.slots, self.shift, G.view(np.uint8), exponents)

    def pending_rows(self, G: np.ndarray, exponents: np.ndarray, values: np.ndarray):
        """``(codes, f, first, todo)``: :meth:`lookup_rows` with each row's value ``values[slot]``
        (NaN where absent) and the absent first occurrences ``todo``, in one pass."""
        return _pending_rows(self.keys, self.slots, self.shift, G.view(np.uint8), exponents, values)

    def store_fresh(self, codes: np.ndarray, values: np.ndarray, keys: np.ndarray, f: np.ndarray,
                    start: int, size: int) -> int:
        """Store keys absent from the index and distinct (at most ``size``) with their finite
        values in the ring ``codes, values`` (``int64`` and float, ``size`` slots at most, in use
        below ``len(self)``) from slot ``start``, dropping the entries they replace; returns the
        next slot."""
        self._room(self.count + keys.size)
        nxt, change = _store_fresh(self.keys, self.slots, self.shift, codes, values, keys, f,
                                   start, self.count, size)
        self.count += int(change)
        return int(nxt)

    def update(self, keys: np.ndarray, slots: np.ndarray) -> None:
        """Set ``keys[i] -> slots[i]`` in order (a later repeat overwrites)."""
        self._room(self.count + keys.size)
        self.count += int(_put_batch(self.keys, self.slots, self.shift, keys, slots.astype(np.int64)))

    def remove(self, keys: np.ndarray) -> None:
        """Delete the keys present among ``keys``."""
        self.count -= int(_remove_batch(self.keys, self.slots, self.shift, keys))

    def _room(self, n: int) -> None:
        """Grow (by powers of two, rehashed) until ``n`` entries fill at most half the table."""
        if 2 * n <= 1 << self.bits:
            return
        bits = max(self.bits, _bits_for(n))
        if bits == self.bits:
            return
        keys, slots = self.keys, self.slots
        self._alloc(bits)
        _rehash(keys, slots, self.keys, self.slots, self.shift)


def _bits_for(n: int) -> int:
    """The table size (a power of two, at least ``2 ** MIN_BITS``) that ``n`` entries fill at
    most half of."""
    return max(MIN_BITS, int(2 * n - 1).bit_length()) if n > 0 else MIN_BITS
