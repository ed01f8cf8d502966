"""Tensor-product Bezier surfaces, and Choi's bicubic test surface (Djebali et al., Table 3).

S(u, v) = sum_i sum_j B_i^p(u) B_j^q(v) P_ij,  (u, v) in [0, 1]^2  (Djebali et al., Sec. 6.4).

The Bernstein form is converted once to the power basis (exact algebra), so a Bezier net
evaluates through :class:`PolynomialSurface`'s two-matmul path. The power basis loses
accuracy for high degrees; nets up to degree ~10 per direction are fine (double precision).
"""

from __future__ import annotations

from math import comb

import numpy as np

from .surface import PolynomialSurface

__all__ = ["BezierSurface", "bernstein_to_power", "choi_poles", "choi_surface"]


def bernstein_to_power(degree: int) -> np.ndarray:
    """M (n+1, n+1) with B_i^n(t) = sum_k M[i, k] t^k."""
    n = degree
    m = np.zeros((n + 1, n + 1))
    for i in range(n + 1):
        for k in range(i, n + 1):
            m[i, k] = comb(n, k) * comb(k, i) * (-1) ** (k - i)
    return m


class BezierSurface(PolynomialSurface):
    """Bezier surface from a control net ``poles``: (p+1, q+1, 3), index i along u, j along v."""

    def __init__(self, poles, normal_sign: float | None = None, name: str = "bezier"):
        p = np.asarray(poles, dtype=float)
        if p.ndim != 3 or p.shape[2] != 3 or p.shape[0] < 2 or p.shape[1] < 2:
            raise ValueError(f"poles: expected shape (p+1, q+1, 3) with p, q >= 1, got {p.shape}")
        self.poles = p
        mu = bernstein_to_power(p.shape[0] - 1)
        mv = bernstein_to_power(p.shape[1] - 1)
        coeffs = np.einsum("ik,ijc,jl->klc", mu, p, mv)
        super().__init__(coeffs, normal_sign=normal_sign, name=name)


def choi_poles() -> np.ndarray:
    """Choi's bicubic net (Djebali et al., Table 3), (4, 4, 3) in mm.

    Table 3 lists four column groups (X = 0, 17.78, 35.56, 50.8) by four rows
    (Y = 0, 25.4, 50.8, 76.2); i runs over the X groups (u), j over the rows (v), so the
    surface is symmetric about Y = 38.1 (v = 0.5) as the paper states.
    """
    xs = [0.0, 17.78, 35.56, 50.8]
    ys = [0.0, 25.4, 50.8, 76.2]
    z_rows = [  # z[j][i]: row j (Y), column group i (X)
        [38.1, 30.48, 38.1, 30.48],
        [30.48, 22.86, 30.48, 22.86],
        [30.48, 22.86, 30.48, 22.86],
        [38.1, 30.48, 38.1, 30.48],
    ]
    p = np.zeros((4, 4, 3))
    for i in range(4):
        for j in range(4):
            p[i, j] = (xs[i], ys[j], z_rows[j][i])
    return p


def choi_surface() -> BezierSurface:
    """Choi's bicubic Bezier test surface (Djebali et al., Sec. 6.4 and Table 3)."""
    return BezierSurface(choi_poles(), name="choi")
