"""Mesh features: the n x m parametric mesh of a surface and, per cell, what zoning needs.

Per cell (Djebali Sec. 3.1 "meshes"; Herraz Sec. 2.1 "sample points" at the cell centres):
(u, v) of the centre, slope angle S = arccos(n_z), steepest-slope direction
phi = atan(n_y / n_x) (Djebali Eq. 1 notation) as an axial angle in [0, pi), the optimal
feed direction (for a toroidal cutter in 3-axis the steepest-slope direction, where Eq. 1
is largest: Djebali Sec. 2.1), and the cell's surface area (2 x 2 Gauss quadrature of
|S_u x S_v|).
"""

from __future__ import annotations

import os

from dataclasses import dataclass

import numpy as np

from ...geometry.surface import Surface
from .samples import graph_derivatives

__all__ = ["MeshFeatures", "mesh_features", "check_mesh"]


def check_mesh(n, m, key: str = "mesh") -> tuple[int, int]:
    """(n, m) as ints >= 1 with n * m >= 2; ValueError naming ``key`` otherwise."""
    try:
        n_i, m_i = int(n), int(m)
    except (TypeError, ValueError):
        raise ValueError(f"{key}: expected two integers [n, m], got {[n, m]!r}") from None
    if n_i != n or m_i != m or n_i < 1 or m_i < 1 or n_i * m_i < 2:
        raise ValueError(f"{key}: a mesh needs at least 2 cells (n, m >= 1 integers), "
                         f"got {n} x {m}")
    need = n_i * m_i * BYTES_PER_CELL
    if need > _memory_limit():
        raise ValueError(f"{key}: a {n_i} x {m_i} mesh needs about {need / 2**30:.1f} GiB, more "
                         f"than half of this machine's memory")
    return n_i, m_i


#: float64 fields per mesh cell over the zoning pipeline (features, samples, labels, passes)
BYTES_PER_CELL = 24 * 8


def _memory_limit() -> float:
    try:
        return 0.5 * os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 8.0 * 2**30


@dataclass(frozen=True)
class MeshFeatures:
    """Per-cell arrays, each (n, m): u, v centre, slope, steepest, optimal feed, area (mm^2)."""

    u: np.ndarray
    v: np.ndarray
    slope: np.ndarray
    steepest: np.ndarray
    optimal_feed: np.ndarray
    area: np.ndarray

    @property
    def shape(self) -> tuple[int, int]:
        return self.u.shape

    @property
    def size(self) -> int:
        return self.u.size


def mesh_features(surface: Surface, n: int, m: int) -> MeshFeatures:
    """Features of the n x m mesh (cells of equal (u, v) size; i along u, j along v)."""
    n, m = check_mesh(n, m)
    cu = (np.arange(n) + 0.5) / n
    cv = (np.arange(m) + 0.5) / m
    uu, vv = np.meshgrid(cu, cv, indexing="ij")
    jet = surface.jet(uu.ravel(), vv.ravel(), order=2)
    p, q, *_ = graph_derivatives(jet)
    slope = np.arctan(np.hypot(p, q)).reshape(n, m)
    steepest = np.mod(np.arctan2(q, p), np.pi).reshape(n, m)
    g = 0.5 / np.sqrt(3.0)  # Gauss points at the cell centre +- g * cell size
    area = np.zeros(n * m)
    for du in (-g, g):
        for dv in (-g, g):
            j1 = surface.jet(uu.ravel() + du / n, vv.ravel() + dv / m, order=1)
            area += 0.25 * np.linalg.norm(np.cross(j1.su, j1.sv), axis=1)
    area = (area / (n * m)).reshape(n, m)
    return MeshFeatures(uu, vv, slope, steepest, steepest.copy(), area)
