"""Exact normal offset surfaces: O(u, v) = S(u, v) + d n(u, v).

The normal is computed from the surface's exact first derivatives (Abbas Eqs. 7-8:
n = S_t x S_s / |S_t x S_s|, here ``surface.unit_normal`` on the analytic jet), not by
offsetting the control net, so every offset point lies at distance exactly |d| from its foot
point along the normal. Used with d = R (ball centre: the CL surface of a ball end mill),
d = R + D_off2 (the semi-finish CL surface), or d = the allowances (the stock left).

Self-intersection: an offset towards the side where the surface is concave folds over itself
where a principal curvature radius is below the offset distance, i.e. where
kappa_max * d > 1 (kappa > 0 concave seen from the tool side, the sign of ``surface.py``).
Those points are flagged: a ball centred there would cut into the surface nearby (gouge).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.surface import principal_curvatures, unit_normal


@dataclass
class Offset:
    """points (n, 3) = foot + distance * normal; normal (n, 3) unit, tool side; foot (n, 3);
    folded (n,) bool: the offset self-intersects there (curvature radius < distance)."""

    points: np.ndarray
    normal: np.ndarray
    foot: np.ndarray
    folded: np.ndarray
    distance: float


def normal_offset(surface, u, v, distance: float) -> Offset:
    """Offset by ``distance`` along the unit normal on the tool side at parameters u, v (n,)."""
    u, v = np.broadcast_arrays(np.asarray(u, float).ravel(), np.asarray(v, float).ravel())
    jet = surface.jet(u, v, order=2)
    n = unit_normal(jet, surface.normal_sign)
    k_min, k_max = principal_curvatures(jet, surface.normal_sign)
    # the side the offset moves to: concave there means kappa_max * d > 1 (d > 0), and for an
    # offset to the other side (d < 0) the convex curvature k_min folds it: k_min * d > 1
    folded = np.maximum(k_max * distance, k_min * distance) > 1.0
    return Offset(jet.p + distance * n, n, jet.p, folded, float(distance))
