"""Where lines cross closed polylines: point-in-domain masks and the sections of pass planes.

Both questions reduce to the crossings of horizontal lines y = q with the edges of closed
loops (the boundary of a trimmed footprint, in (u, v) or in XY). An edge (a, b) crosses the
line when exactly one of its ends lies above it, ``(a_y > q) != (b_y > q)`` (the half-open
rule: a line through a vertex counts it once, so every line crosses a closed loop an even
number of times), at ``x = a_x + (q - a_y) (b_x - a_x) / (b_y - a_y)``.

- :func:`inside`: a point is inside by the even-odd rule when an odd number of crossings of
  its line lie to its right (over all loops: a hole is a loop inside the outer one);
- :func:`line_intervals`: the stretches of each line inside the loops, between crossings
  taken in pairs after sorting.

The edges are bucketed by the rows of y they span, so each query only meets the few edges
of its row: the work is linear in the number of queries, not in queries x edges.
"""

from __future__ import annotations

import numpy as np

from .rows import ranges

__all__ = ["edges_of", "inside", "inside_grid", "line_crossings", "line_intervals"]

_PAIRS = 1 << 22  # (query, edge) pairs per batch


def edges_of(loops) -> tuple[np.ndarray, np.ndarray]:
    """(a, b): the edges (m, 2) each of closed loops (each (k, 2), closed implicitly)."""
    a = [np.asarray(lp, float) for lp in loops]
    return np.concatenate(a), np.concatenate([np.roll(lp, -1, axis=0) for lp in a])


class _Buckets:
    """The non-horizontal edges grouped by the rows of y (``n_rows`` equal rows) they span."""

    def __init__(self, a, b, n_rows: int | None = None):
        keep = a[:, 1] != b[:, 1]
        self.a, self.b = a[keep], b[keep]
        ylo = np.minimum(self.a[:, 1], self.b[:, 1])
        yhi = np.maximum(self.a[:, 1], self.b[:, 1])
        m = len(self.a)
        self.n = int(np.clip(m if n_rows is None else n_rows, 1, 1 << 14))
        self.y0 = float(ylo.min()) if m else 0.0
        span = (float(yhi.max()) - self.y0) if m else 1.0
        self.h = span / self.n if span > 0 else 1.0
        r0, r1 = self.row(ylo), self.row(yhi)
        owner, k = ranges(r1 - r0 + 1)
        rows = r0[owner] + k
        order = np.argsort(rows, kind="stable")
        self.edge = owner[order]
        self.start = np.searchsorted(rows[order], np.arange(self.n + 1))

    def row(self, y):
        return np.clip(np.floor((np.asarray(y, float) - self.y0) / self.h).astype(np.int64),
                       0, self.n - 1)

    def pairs(self, q):
        """Batches of (query index, x of the crossing) for the lines y = q (n,)."""
        q = np.asarray(q, float)
        if not len(self.a) or not len(q):
            return
        r = self.row(q)
        count = self.start[r + 1] - self.start[r]
        cum = np.cumsum(count)
        lo = 0
        while lo < len(q):
            base = cum[lo - 1] if lo else 0
            hi = int(np.searchsorted(cum, base + _PAIRS, side="right"))
            hi = min(max(hi, lo + 1), len(q))
            owner, k = ranges(count[lo:hi])
            owner = owner + lo
            e = self.edge[self.start[r[owner]] + k]
            a, b, y = self.a[e], self.b[e], q[owner]
            hit = (a[:, 1] > y) != (b[:, 1] > y)
            a, b, y, owner = a[hit], b[hit], y[hit], owner[hit]
            x = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
            yield owner, x
            lo = hi


def inside(loops, x, y) -> np.ndarray:
    """Even-odd mask (n,) of the points (x, y) in the domain bounded by ``loops``."""
    x = np.asarray(x, float).ravel()
    y = np.asarray(y, float).ravel()
    odd = np.zeros(len(x), np.int64)
    for owner, xc in _Buckets(*edges_of(loops)).pairs(y):
        odd += np.bincount(owner, weights=xc > x[owner], minlength=len(x)).astype(np.int64)
    return (odd % 2) == 1


def line_crossings(loops, q) -> tuple[np.ndarray, np.ndarray]:
    """(line index, x) of every crossing of the lines y = q (n,) with the loops, sorted by
    line then x."""
    parts = list(_Buckets(*edges_of(loops)).pairs(q))
    if not parts:
        return np.zeros(0, np.int64), np.zeros(0)
    owner = np.concatenate([p[0] for p in parts])
    x = np.concatenate([p[1] for p in parts])
    order = np.lexsort((x, owner))
    return owner[order], x[order]


def line_intervals(loops, q):
    """(line index, x_a, x_b, first, last) of the stretches of the lines y = q inside the
    loops (even-odd), in order along each line; ``first`` / ``last`` mark each line's first
    and last stretch. A line with an odd count of crossings (it grazes a vertex within
    round-off) drops its last one."""
    owner, x = line_crossings(loops, q)
    if not len(owner):
        z = np.zeros(0)
        return np.zeros(0, np.int64), z, z, z.astype(bool), z.astype(bool)
    new = np.r_[True, owner[1:] != owner[:-1]]
    group_start = np.flatnonzero(new)
    rank = np.arange(len(owner)) - np.repeat(group_start, np.diff(np.r_[group_start, len(owner)]))
    size = np.bincount(owner, minlength=int(owner.max()) + 1)[owner]
    opener = (rank % 2 == 0) & (rank + 1 < size)
    i = np.flatnonzero(opener)
    line, xa, xb = owner[i], x[i], x[i + 1]
    first = rank[i] == 0
    last = rank[i] + 2 >= size[i] - (size[i] % 2)
    return line, xa, xb, first, last


def inside_grid(loops, xs, ys) -> np.ndarray:
    """Even-odd mask (ny, nx) of the cell centres xs (nx,) x ys (ny,) of a regular grid: one
    line per row, its crossings sorted once, each cell ranked among them (a scanline fill)."""
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    row, x = line_crossings(loops, ys)
    per_row = np.bincount(row, minlength=len(ys))
    if not len(x):
        return np.zeros((len(ys), len(xs)), bool)
    lo = min(float(x.min()), float(xs.min()))
    width = max(float(x.max()), float(xs.max())) - lo + 1.0
    keys = row * width + (x - lo)  # ascending: sorted by row, then x
    cells = np.arange(len(ys))[:, None] * width + (xs[None, :] - lo)
    right = np.cumsum(per_row)[:, None] - np.searchsorted(keys, cells, side="right")
    return (right % 2) == 1
