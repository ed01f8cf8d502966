"""The lower profile of a cutter from its kernel array, compiled: for the numba kernels of
the cut simulation (its bounds) and the drop-cutter's seeds.

``Cutter.kernel_params`` describes the solid as convex pieces of revolution (a cylinder, a
torus or sphere, a cone frustum); :func:`piece_height` is the lowest height of those pieces
above the tip at a radial distance from the axis, the profile ``Cutter.height_jet`` gives
in numpy (as a function of s = rho^2 / 2).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

INF = np.inf

#: the layout of a cutter's kernel array (``Cutter.kernel_params``, which the cut
#: simulation's ``kernel.py`` and :func:`piece_height` read): [R, n, then n pieces of PIECE
#: slots each: code, then its parameters]; R the outer radius (every piece lies within it),
#: the pieces convex solids of revolution whose union is the cutter
PIECE = 6
#: the shank or a flat end: {rho <= R, w >= w_lo}; parameters (w_lo)
CYLINDER = 1
#: points within q of the disc of radius e at height c: (e, c, q); a sphere for e = 0 (the
#: ball), the flat bottom and corner torus of a toroidal cutter for e > 0
ROUND = 2
#: a cone frustum {rho <= (w - w_a) tan beta, w_lo <= w <= w_hi}: (w_a, sin beta,
#: cos beta, w_lo, w_hi) (the taper of a tapered cutter)
CONE = 3


@njit(cache=True, nogil=True, error_model="numpy")
def piece_height(rho, prm):
    """h(rho): the lower profile of the cutter (the lowest w of its pieces) at radial distance
    rho from the axis; inf beyond the radius (or where no piece reaches)."""
    if rho > prm[0]:
        return INF
    h = INF
    for k in range(int(prm[1])):
        b = 2 + PIECE * k
        code = prm[b]
        if code == CYLINDER:
            h = min(h, prm[b + 1])
        elif code == ROUND:
            e, c, q = prm[b + 1], prm[b + 2], prm[b + 3]
            if rho <= e:
                h = min(h, c - q)
            elif rho <= e + q:
                h = min(h, c - math.sqrt(max(q * q - (rho - e) ** 2, 0.0)))
        else:
            wa, sb, cb, lo, hi = prm[b + 1], prm[b + 2], prm[b + 3], prm[b + 4], prm[b + 5]
            w = wa + rho * cb / sb
            if w <= hi:
                h = min(h, max(w, lo))
    return h


@njit(cache=True, nogil=True, error_model="numpy")
def window_bottom(p, tips, reach, prm):
    """(M,): over each point p[i] (M, >= 2: x, y), the lowest bottom of a vertical cutter
    at the tips (M, 3) of indices i - reach .. i + reach (clipped to the ends): the least
    tip z + h(rho), rho the XY distance from the point to the tip (inf where none reaches).
    The sweep of a pass along its feed near each of its points."""
    m = tips.shape[0]
    out = np.empty(p.shape[0])
    for i in range(p.shape[0]):
        low = INF
        for k in range(i - reach, i + reach + 1):
            j = min(max(k, 0), m - 1)
            dx, dy = p[i, 0] - tips[j, 0], p[i, 1] - tips[j, 1]
            z = tips[j, 2] + piece_height(math.sqrt(dx * dx + dy * dy), prm)
            if z < low:
                low = z
        out[i] = low
    return out
