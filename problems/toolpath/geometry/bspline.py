"""Tensor-product B-spline surfaces, evaluated by ``spline_kernel.spline_jet`` (numba).

S(u, v) = sum_i sum_j N_i^p(u) N_j^q(v) P_ij over the knot vectors (Piegl & Tiller, Eq. 3.11).
The parameters exposed to the engine are rescaled to [0, 1]^2 (derivatives are scaled
accordingly); the knot vectors may span any interval.
"""

from __future__ import annotations

import numpy as np

from .spline_kernel import spline_jet
from .surface import Jet, Surface

__all__ = ["BSplineSurface", "clamped_uniform_knots"]


def clamped_uniform_knots(n_poles: int, degree: int) -> np.ndarray:
    """Open (clamped) uniform knot vector on [0, 1]: n_poles + degree + 1 knots."""
    inner = np.linspace(0.0, 1.0, n_poles - degree + 1)
    return np.concatenate([np.zeros(degree), inner, np.ones(degree)])


class BSplineSurface(Surface):
    """B-spline surface: poles (nu, nv, 3), degrees (p, q), optional knot vectors.

    Knots default to clamped uniform; given knots must be non-decreasing with
    len = n_poles + degree + 1 (checked by the spec parser, which names the key).
    """

    def __init__(self, poles, degree=(3, 3), knots_u=None, knots_v=None,
                 normal_sign: float | None = None, name: str = "bspline"):
        p = np.asarray(poles, dtype=float)
        self.poles = p
        self.degree = (int(degree[0]), int(degree[1]))
        ku, kv = self.degree
        tu = clamped_uniform_knots(p.shape[0], ku) if knots_u is None else np.asarray(knots_u, float)
        tv = clamped_uniform_knots(p.shape[1], kv) if knots_v is None else np.asarray(knots_v, float)
        self.knots = (tu, tv)
        self._lo = np.array([tu[ku], tv[kv]])
        self._span = np.array([tu[-ku - 1] - tu[ku], tv[-kv - 1] - tv[kv]])
        self._poles = np.ascontiguousarray(p, dtype=float)
        self.name = name
        self._orient(normal_sign)

    def jet(self, u, v, order: int = 2) -> Jet:
        """Jet up to ``order`` at u, v in [0, 1]: (n,) -> Jet with (n, 3) fields."""
        xi = np.stack([np.asarray(u, float), np.asarray(v, float)], axis=-1)
        xi = self._lo + np.clip(xi, 0.0, 1.0) * self._span
        su, sv = self._span
        order = min(int(order), 2)
        jet = spline_jet(self._poles, self.knots[0], self.knots[1], self.degree[0],
                         self.degree[1], np.ascontiguousarray(xi[..., 0].ravel()),
                         np.ascontiguousarray(xi[..., 1].ravel()), order)
        scale = (1.0, su, sv, su * su, su * sv, sv * sv)
        return Jet(*(jet[:, i] * scale[i] for i in range(jet.shape[1])))
