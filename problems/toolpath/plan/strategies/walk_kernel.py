"""The compiled step of a walk across the surface (``offsets.march``, ``offsets.cusp_heights``):
the (u, v) rate of a unit-speed walk along a tangent direction, one pass over the points."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["walk_rate"]


@njit(cache=True, nogil=True, error_model="numpy")
def walk_rate(su, sv, n, d):
    """((M, 2), (M, 3)): for each point, d (M, 3) projected onto the tangent plane of unit
    normal n and made unit, and the (u, v) rate that moves along it at unit speed: the
    solution of [E F; F G] (du, dv) = (su . d, sv . d), E, F, G the first fundamental form
    of the partial derivatives su, sv (M, 3)."""
    m = d.shape[0]
    rate = np.empty((m, 2))
    out = np.empty((m, 3))
    for i in range(m):
        k = d[i, 0] * n[i, 0] + d[i, 1] * n[i, 1] + d[i, 2] * n[i, 2]
        x, y, z = d[i, 0] - k * n[i, 0], d[i, 1] - k * n[i, 1], d[i, 2] - k * n[i, 2]
        norm = max(math.sqrt(x * x + y * y + z * z), 1e-300)
        x, y, z = x / norm, y / norm, z / norm
        a0, a1, a2 = su[i, 0], su[i, 1], su[i, 2]
        b0, b1, b2 = sv[i, 0], sv[i, 1], sv[i, 2]
        e = a0 * a0 + a1 * a1 + a2 * a2
        f = a0 * b0 + a1 * b1 + a2 * b2
        g = b0 * b0 + b1 * b1 + b2 * b2
        r1 = a0 * x + a1 * y + a2 * z
        r2 = b0 * x + b1 * y + b2 * z
        det = e * g - f * f
        rate[i, 0] = (g * r1 - f * r2) / det
        rate[i, 1] = (e * r2 - f * r1) / det
        out[i, 0], out[i, 1], out[i, 2] = x, y, z
    return rate, out
