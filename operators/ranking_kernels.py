"""The compiled form of :func:`evoplan.operators.ranking.stable_order` (numba)."""

from __future__ import annotations

import numba
import numpy as np

DIGIT_BITS = 11
BUCKETS = 1 << DIGIT_BITS
SIGN = np.uint64(1) << np.uint64(63)


@numba.njit(cache=True)
def radix_order(f):
    """``np.argsort(f, kind="stable")`` for ``f: (n,) float64`` with NaN taken as ``inf``, by a least-significant
    digit radix sort of the values' bit patterns (six passes of 11 bits; a pass whose digit is
    the same for every value is skipped, as the high digits of a converging population are).

    A stable sort's permutation is unique, so this is numpy's bit for bit: values map to
    unsigned keys in the order of the reals (negative: all bits flipped; else the sign bit
    set), -0.0 taken as 0.0 (numpy ranks them equal, first come first)."""
    n = f.size
    keys = np.empty(n, dtype=np.uint64)
    g = np.empty(n)
    for i in range(n):
        x = f[i] + 0.0  # (-0.0 + 0.0 is 0.0)
        g[i] = np.inf if x != x else x
    bits = g.view(np.uint64)
    for i in range(n):
        b = bits[i]
        keys[i] = ~b if b & SIGN else b | SIGN
    order = np.arange(n)
    spare_order = np.empty(n, dtype=np.int64)
    spare_keys = np.empty(n, dtype=np.uint64)
    count = np.empty(BUCKETS, dtype=np.int64)
    mask = np.uint64(BUCKETS - 1)
    for p in range(0, 64, DIGIT_BITS):
        shift = np.uint64(p)
        count[:] = 0
        for i in range(n):
            count[(keys[i] >> shift) & mask] += 1
        if n == 0 or count[(keys[0] >> shift) & mask] == n:
            continue  # every value has this digit: the pass would not move anything
        total = 0
        for d in range(BUCKETS):
            c = count[d]
            count[d] = total
            total += c
        for i in range(n):
            d = (keys[i] >> shift) & mask
            j = count[d]
            count[d] = j + 1
            spare_keys[j] = keys[i]
            spare_order[j] = order[i]
        keys, spare_keys = spare_keys, keys
        order, spare_order = spare_order, order
    return order
