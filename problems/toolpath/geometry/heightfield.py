"""A height field z = f(x, y) over a rectangle, f a bicubic tensor-product B-spline.

As a parametric surface over the unit square: S(u, v) = (x0 + u Lx, y0 + v Ly, f(x, y)), so

- S_u = (Lx, 0, f_x Lx),  S_v = (0, Ly, f_y Ly),
- S_uu = (0, 0, f_xx Lx^2),  S_uv = (0, 0, f_xy Lx Ly),  S_vv = (0, 0, f_yy Ly^2),

and S_u x S_v = Lx Ly (-f_x, -f_y, 1) points up: a height field is its own graph over XY.
f(x, y) = sum_ij N_i^3(x) N_j^3(y) c_ij (Piegl & Tiller, Eq. 3.11, scalar coefficients),
evaluated with ``scipy.interpolate.NdBSpline``; (u, v) outside [0, 1]^2 are clipped as
:class:`~.bspline.BSplineSurface` clips them.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import NdBSpline

from .surface import Jet, Surface

__all__ = ["HeightFieldSurface"]


class HeightFieldSurface(Surface):
    """``knots`` (tx, ty) over [x0, x0 + Lx] and [y0, y0 + Ly], ``coeffs`` (nx, ny), cubic."""

    def __init__(self, knots, coeffs, bounds, name: str = "heightfield"):
        tx, ty = (np.asarray(t, float) for t in knots)
        self.knots = (tx, ty)
        self.coeffs = np.asarray(coeffs, float)
        x0, x1, y0, y1 = (float(b) for b in bounds)
        self.bounds = (x0, x1, y0, y1)
        self._lo = np.array([x0, y0])
        self._span = np.array([x1 - x0, y1 - y0])
        self._f = NdBSpline((tx, ty), self.coeffs, 3)
        self.name = name
        self.normal_sign = 1.0

    def height(self, x, y, dx: int = 0, dy: int = 0) -> np.ndarray:
        """f (or its partial d^(dx+dy) f / dx^dx dy^dy) at the points (x, y), mm."""
        xi = np.stack([np.asarray(x, float).ravel(), np.asarray(y, float).ravel()], axis=-1)
        return self._f(xi, nu=(dx, dy))

    def jet(self, u, v, order: int = 2) -> Jet:
        """Jet up to ``order`` at u, v in [0, 1]: (n,) -> Jet with (n, 3) fields."""
        uv = np.clip(np.stack([np.asarray(u, float), np.asarray(v, float)], axis=-1), 0.0, 1.0)
        xi = self._lo + uv * self._span
        lx, ly = self._span
        n = len(xi)
        f = self._f
        p = np.empty((n, 3))
        p[:, :2] = xi
        p[:, 2] = f(xi)
        if order < 1:
            return Jet(p)
        su = np.zeros((n, 3))
        sv = np.zeros((n, 3))
        su[:, 0], sv[:, 1] = lx, ly
        su[:, 2] = f(xi, nu=(1, 0)) * lx
        sv[:, 2] = f(xi, nu=(0, 1)) * ly
        if order < 2:
            return Jet(p, su, sv)
        second = [np.zeros((n, 3)) for _ in range(3)]
        second[0][:, 2] = f(xi, nu=(2, 0)) * lx * lx
        second[1][:, 2] = f(xi, nu=(1, 1)) * lx * ly
        second[2][:, 2] = f(xi, nu=(0, 2)) * ly * ly
        return Jet(p, su, sv, *second)
