"""Row-wise vector operations on (n, 2) and (n, 3) arrays, bit for bit numpy's general
routines without their overheads.

``np.linalg.norm(a, axis=-1)`` squares into a temporary and reduces along a short axis,
which numpy runs as a strided loop per row: 10x slower on 130 000 rows than the same
sum written out by column. Its reduction over a row of two or three adds left to right,
so ``sqrt((x*x + y*y) + z*z)`` is the same number. ``a[idx]`` on a 2-D array gathers
through numpy's general fancy indexing; ``np.take(a, idx, axis=0)`` copies the same rows
3-4x faster (measured on a 5-axis plan batch: 1.31 against 0.34 ms for 133 000 points).
``np.cross`` moves axes and casts before the products :func:`cross_rows` writes out in its
order (6.3 against 0.87 ms for 133 000 rows).
"""

from __future__ import annotations

import numpy as np

__all__ = ["cross_rows", "row_norms", "take_rows"]


def row_norms(a) -> np.ndarray:
    """``np.linalg.norm(a, axis=-1)`` for a (..., 2) or (..., 3) float array, the same bits."""
    a = np.asarray(a, float)
    if a.shape[-1] == 2:
        x, y = a[..., 0], a[..., 1]
        return np.sqrt(x * x + y * y)
    if a.shape[-1] == 3:
        x, y, z = a[..., 0], a[..., 1], a[..., 2]
        return np.sqrt(x * x + y * y + z * z)
    return np.linalg.norm(a, axis=-1)


def take_rows(a, idx) -> np.ndarray:
    """``a[idx]`` for an integer index array ``idx`` (the rows of a, in idx's order)."""
    a = np.asarray(a)
    return np.take(a, idx, axis=0)


def cross_rows(a, b) -> np.ndarray:
    """``np.cross(a, b)`` for float arrays of 3-vectors on their last axis (broadcast), the
    same products and differences in numpy's order, so the same bits."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    np.subtract(a[..., 1] * b[..., 2], a[..., 2] * b[..., 1], out=out[..., 0])
    np.subtract(a[..., 2] * b[..., 0], a[..., 0] * b[..., 2], out=out[..., 1])
    np.subtract(a[..., 0] * b[..., 1], a[..., 1] * b[..., 0], out=out[..., 2])
    return out
