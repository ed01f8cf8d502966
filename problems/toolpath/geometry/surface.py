"""Parametric surfaces and their differential geometry, batched over arrays of (u, v).

A surface maps the unit square (u, v) in [0, 1]^2 to R^3. Every surface here returns a
:class:`Jet` (the point and its first and second partial derivatives) for whole arrays of
parameters at once; the differential geometry (unit normal, fundamental forms, normal and
principal curvatures) is computed from a jet by the module functions below.

Sign convention (used throughout the engine): the unit normal points to the tool side
(``+z`` for the shipped surfaces: the tool comes from above), and a normal curvature is
``II(d, d) / I(d, d)`` with that normal, so **kappa > 0 means the surface bends towards the
tool (concave seen from the tool)** and kappa < 0 convex. This is the sign of the reference
value in ``docs/toolpath_formulas.md`` (Fountas' surface at (0.7, 0.5): +0.0159 /mm across an
X feed, concave).

Shipped surfaces:

- :func:`fountas_surface`: Fountas et al., Eq. 14, the benchmark part (a biquadratic
  polynomial, evaluated exactly in the power basis).
- :class:`BezierSurface` (``bezier.py``): tensor-product Bezier nets, Choi's bicubic surface.
- :class:`BSplineSurface` (``bspline.py``): tensor-product B-spline nets (scipy).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .footprint import UNIT_SQUARE, Footprint
from .vectors import cross_rows, row_norms

__all__ = [
    "Jet",
    "Surface",
    "PolynomialSurface",
    "fountas_surface",
    "unit_normal",
    "fundamental_forms",
    "normal_curvature",
    "principal_curvatures",
]


class Jet(NamedTuple):
    """Point and partial derivatives at n parameter pairs; each field (n, 3) or None."""

    p: np.ndarray
    su: np.ndarray | None = None
    sv: np.ndarray | None = None
    suu: np.ndarray | None = None
    suv: np.ndarray | None = None
    svv: np.ndarray | None = None


class Surface:
    """Base class: a parametric surface over (u, v) in [0, 1]^2.

    Subclasses implement :meth:`jet`. ``normal_sign`` (+1 or -1) orients ``su x sv`` to the
    tool side; it is chosen at construction so that the normal at the domain centre has a
    non-negative z component (tool above the part), unless given explicitly.
    """

    normal_sign: float = 1.0
    #: where the surface is material in (u, v) (``footprint.py``): the unit square unless trimmed
    footprint: Footprint = UNIT_SQUARE

    def facts(self) -> dict:
        """What every output records about the surface beyond its settings (a mesh: the file
        and the fit's measured deviation, ``mesh_surface.py``); empty for an exact surface."""
        return {}

    def jet(self, u, v, order: int = 2) -> Jet:  # pragma: no cover - abstract
        """Derivatives up to ``order`` (0, 1 or 2) at u, v: (n,) each -> Jet of (n, 3)."""
        raise NotImplementedError

    def _orient(self, normal_sign: float | None) -> None:
        if normal_sign is None:
            j = self.jet(np.array([0.5]), np.array([0.5]), order=1)
            z = np.cross(j.su, j.sv)[0, 2]
            normal_sign = 1.0 if z >= 0 else -1.0
        self.normal_sign = float(normal_sign)

    # Convenience wrappers over the module functions ------------------------------------
    def points(self, u, v) -> np.ndarray:
        """Surface points, u, v: (n,) -> (n, 3)."""
        u, v = _as_uv(u, v)
        return self.jet(u, v, order=0).p

    def normals(self, u, v) -> np.ndarray:
        """Unit normals on the tool side, (n,) -> (n, 3)."""
        u, v = _as_uv(u, v)
        return unit_normal(self.jet(u, v, order=1), self.normal_sign)

    def normal_curvature(self, u, v, direction) -> np.ndarray:
        """Normal curvature (1/mm, > 0 concave seen from the tool) along 3D directions (n, 3)."""
        u, v = _as_uv(u, v)
        return normal_curvature(self.jet(u, v, order=2), direction, self.normal_sign)

    def principal_curvatures(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """Principal curvatures (k_min, k_max), each (n,), same sign convention."""
        u, v = _as_uv(u, v)
        return principal_curvatures(self.jet(u, v, order=2), self.normal_sign)


def _as_uv(u, v):
    u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
    return u.ravel(), v.ravel()


# -------------------------------------------------------------------------------------
# Polynomial surfaces in the power basis (Fountas Eq. 14; Bezier nets convert to this)
# -------------------------------------------------------------------------------------

_ORDERS = {0: [(0, 0)], 1: [(0, 0), (1, 0), (0, 1)],
           2: [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]}


def _derive(a: np.ndarray, du: int, dv: int) -> np.ndarray:
    """Coefficients of d^(du+dv) S / du^du dv^dv, padded back to a's shape."""
    out = a.copy()
    for _ in range(du):
        i = np.arange(1, out.shape[0])[:, None, None]
        out = np.concatenate([out[1:] * i, np.zeros_like(out[:1])], axis=0)
    for _ in range(dv):
        j = np.arange(1, out.shape[1])[None, :, None]
        out = np.concatenate([out[:, 1:] * j, np.zeros_like(out[:, :1])], axis=1)
    return out


class PolynomialSurface(Surface):
    """S(u, v) = sum_ij A[i, j] u^i v^j, A: (p+1, q+1, 3) power-basis coefficients.

    Evaluated as one matrix product per batch: the derivative coefficient arrays are stacked
    once at construction, so a jet of order 2 at n points is the (n, (p+1)(q+1)) monomial
    basis times a ((p+1)(q+1), 18) matrix.
    """

    def __init__(self, coeffs, normal_sign: float | None = None, name: str = "polynomial"):
        a = np.asarray(coeffs, dtype=float)
        if a.ndim != 3 or a.shape[2] != 3:
            raise ValueError(f"coeffs: expected shape (p+1, q+1, 3), got {a.shape}")
        self.coeffs = a
        self.name = name
        p1, q1 = a.shape[:2]
        self._shape = (p1, q1)
        # per order: C ((p+1)(q+1), Q*3), so that jet values = basis(u, v) @ C
        self._stacks = {}
        for order, pairs in _ORDERS.items():
            c = np.stack([_derive(a, du, dv) for du, dv in pairs], axis=2)  # (p+1, q+1, Q, 3)
            self._stacks[order] = np.ascontiguousarray(c.reshape(p1 * q1, -1))
        self._stacks_t = {k: np.ascontiguousarray(c.T) for k, c in self._stacks.items()}
        self._orient(normal_sign)

    def jet(self, u, v, order: int = 2) -> Jet:
        """Jet up to ``order`` at u, v: (n,) -> Jet with (n, 3) fields."""
        u = np.asarray(u, float)
        v = np.asarray(v, float)
        p1, q1 = self._shape
        upow = [np.ones_like(u), u]
        vpow = [np.ones_like(v), v]
        for _ in range(2, p1):
            upow.append(upow[-1] * u)
        for _ in range(2, q1):
            vpow.append(vpow[-1] * v)
        basis = np.empty((p1 * q1, len(u)))  # monomials as rows: fast elementwise products
        for i in range(p1):
            for j in range(q1):
                np.multiply(upow[i], vpow[j], out=basis[i * q1 + j])
        vals = (self._stacks_t[order] @ basis).T.reshape(len(u), -1, 3)
        return Jet(*(vals[:, i] for i in range(vals.shape[1])))


def fountas_surface() -> PolynomialSurface:
    """Fountas et al., Eq. 14: the benchmark part, u, v in [0, 1] (mm).

    x = -94.4 + 88.9 v + 5.6 v^2,  y = -131.3 u + 28.1 u^2,
    z = 5.9 (u^2 v^2 + u^2 v) - 3.9 v^2 u + 76.2 u^2 + 6.7 v^2 - 27.3 u v - 50.8 u + 25 v + 12.1

    x depends on v only and y on u only, so the footprint is the rectangle
    [-94.4, 0.1] x [-103.2, 0] and a pass at constant y (X feed) is an iso-u curve.
    """
    a = np.zeros((3, 3, 3))
    a[0, 0, 0], a[0, 1, 0], a[0, 2, 0] = -94.4, 88.9, 5.6
    a[1, 0, 1], a[2, 0, 1] = -131.3, 28.1
    z = a[:, :, 2]
    z[2, 2] += 5.9
    z[2, 1] += 5.9
    z[1, 2] += -3.9
    z[2, 0] += 76.2
    z[0, 2] += 6.7
    z[1, 1] += -27.3
    z[1, 0] += -50.8
    z[0, 1] += 25.0
    z[0, 0] += 12.1
    return PolynomialSurface(a, name="fountas")


# -------------------------------------------------------------------------------------
# Differential geometry on jets
# -------------------------------------------------------------------------------------

def unit_normal(jet: Jet, sign: float = 1.0) -> np.ndarray:
    """Unit normal sign * (su x sv)/|su x sv|: (n, 3). The cross product and the norm
    written out by component (``vectors.py``): the operations of ``np.cross`` and
    ``np.linalg.norm`` in their order (the same numbers bit for bit, tested), without their
    axis shuffles (2-2.5x faster on 300-30 000 points, the sizes a plan evaluates)."""
    n = cross_rows(jet.su, jet.sv)
    n *= sign
    return n / row_norms(n)[..., None]


def fundamental_forms(jet: Jet, sign: float = 1.0, normal=None):
    """(E, F, G, L, M, N, normal): first and second fundamental forms, each (n,);
    ``normal``: the jet's :func:`unit_normal` when the caller has it already."""
    n = unit_normal(jet, sign) if normal is None else normal
    e = np.einsum("ij,ij->i", jet.su, jet.su)
    f = np.einsum("ij,ij->i", jet.su, jet.sv)
    g = np.einsum("ij,ij->i", jet.sv, jet.sv)
    el = np.einsum("ij,ij->i", jet.suu, n)
    m = np.einsum("ij,ij->i", jet.suv, n)
    nn = np.einsum("ij,ij->i", jet.svv, n)
    return e, f, g, el, m, nn, n


def normal_curvature(jet: Jet, direction, sign: float = 1.0, normal=None) -> np.ndarray:
    """Normal curvature along tangent directions (n, 3): II(d, d) / I(d, d), (n,).

    The direction is projected on the tangent plane and expressed in the (su, sv) basis by
    the 2x2 normal equations; > 0 means concave seen from the tool (see module docstring).
    ``normal``: the jet's :func:`unit_normal` (with this ``sign``) when the caller has it.
    """
    e, f, g, el, m, nn, n = fundamental_forms(jet, sign, normal)
    d = np.asarray(direction, float)
    d = d - np.einsum("ij,ij->i", d, n)[:, None] * n
    bu = np.einsum("ij,ij->i", jet.su, d)
    bv = np.einsum("ij,ij->i", jet.sv, d)
    det = e * g - f * f
    a = (g * bu - f * bv) / det
    b = (e * bv - f * bu) / det
    return (el * a * a + 2 * m * a * b + nn * b * b) / (e * a * a + 2 * f * a * b + g * b * b)


def principal_curvatures(jet: Jet, sign: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Principal curvatures (k_min, k_max), (n,) each: roots of det(II - k I) = 0."""
    e, f, g, el, m, nn, _ = fundamental_forms(jet, sign)
    det = e * g - f * f
    h = (e * nn - 2 * f * m + g * el) / (2 * det)  # mean curvature
    k = (el * nn - m * m) / det  # Gaussian curvature
    disc = np.sqrt(np.maximum(h * h - k, 0.0))
    return h - disc, h + disc
