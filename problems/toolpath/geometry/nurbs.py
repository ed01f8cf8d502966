"""Rational (NURBS) tensor-product surfaces: exact cylinders, spheres and other conics.

S(u, v) = sum_ij N_i^p(u) N_j^q(v) w_ij P_ij / sum_ij N_i^p(u) N_j^q(v) w_ij
(Piegl & Tiller, The NURBS Book, Eq. 4.15). The surface is evaluated as the non-rational
B-spline A(u, v) = sum N N (w P, w) in homogeneous coordinates (one B-spline with four
values per pole), then projected. Its derivatives follow from differentiating A = w S by
the product rule and solving for the derivative of S (the quotient rule, written for curves
as Eq. 4.8 and for surfaces as Eq. 4.20 in that book):

- S_u  = (A_u - w_u S) / w,                 S_v likewise;
- S_uu = (A_uu - 2 w_u S_u - w_uu S) / w,   S_vv likewise;
- S_uv = (A_uv - w_u S_v - w_v S_u - w_uv S) / w.

All of it is vectorized over the batch of (u, v). Parameters are rescaled to [0, 1]^2 as
in :class:`BSplineSurface`.
"""

from __future__ import annotations

import numpy as np

from .bspline import BSplineSurface
from .surface import Jet

__all__ = ["NURBSSurface"]


class NURBSSurface(BSplineSurface):
    """NURBS surface: poles (nu, nv, 3), weights (nu, nv) > 0, degrees, optional knots."""

    def __init__(self, poles, weights, degree=(3, 3), knots_u=None, knots_v=None,
                 normal_sign: float | None = None, name: str = "nurbs"):
        p = np.asarray(poles, dtype=float)
        w = np.asarray(weights, dtype=float)
        if w.shape != p.shape[:2] or not np.all(w > 0):
            raise ValueError(f"weights: expected shape {p.shape[:2]} of positive numbers, "
                             f"got {w.shape}")
        self.weights = w
        homogeneous = np.concatenate([p * w[..., None], w[..., None]], axis=2)
        super().__init__(homogeneous, degree, knots_u, knots_v, normal_sign=1.0, name=name)
        self.poles = p
        self._orient(normal_sign)

    def jet(self, u, v, order: int = 2) -> Jet:
        """Jet up to ``order`` at u, v in [0, 1]: (n,) -> Jet with (n, 3) fields."""
        h = super().jet(u, v, order)  # homogeneous jet: (n, 4) fields
        w = h.p[:, 3:]
        inv = 1.0 / w
        s = h.p[:, :3] * inv
        if order < 1:
            return Jet(s)
        wu, wv = h.su[:, 3:], h.sv[:, 3:]
        su = (h.su[:, :3] - wu * s) * inv
        sv = (h.sv[:, :3] - wv * s) * inv
        if order < 2:
            return Jet(s, su, sv)
        suu = (h.suu[:, :3] - 2.0 * wu * su - h.suu[:, 3:] * s) * inv
        suv = (h.suv[:, :3] - wu * sv - wv * su - h.suv[:, 3:] * s) * inv
        svv = (h.svv[:, :3] - 2.0 * wv * sv - h.svv[:, 3:] * s) * inv
        return Jet(s, su, sv, suu, suv, svv)
