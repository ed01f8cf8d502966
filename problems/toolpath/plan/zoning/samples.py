"""Dense samples of a surface seen as a graph z(x, y), for 3-axis zoning.

Zoning works with a 3-axis cutter (tool axis = z, Djebali et al. Sec. 2), so everything it
needs is a property of the graph z(x, y) of the part: the slope angle S and steepest-slope
direction phi (Djebali Eq. 1: cos S = n_z, phi = atan(n_y / n_x)), the slope along a feed
direction, and the Hessian, which gives the normal curvature across any feed.

The samples are the centres of a regular grid in (u, v) (so every sample knows its mesh
cell exactly), each with its XY area weight |det J| du dv. The derivatives of z in XY come
from the parametric jet by the chain rule, with J = d(x, y)/d(u, v):

    (p, q) = grad z = J^-T (z_u, z_v)
    H = J^-T (Z_uv - p X_uv - q Y_uv) J^-1

where Z_uv, X_uv, Y_uv are the 2x2 second-derivative matrices of z, x and y. With the
normal n = (-p, -q, 1) / W, W = sqrt(1 + p^2 + q^2) on the tool side, the second fundamental
form in the (x, y) parameters is H / W and the first is I = [[1 + p^2, pq], [pq, 1 + q^2]],
so a curvature > 0 is concave seen from the tool (the engine's sign, ``geometry/surface.py``).

Assumption: the surface is a graph over XY (det J never 0 on the domain); a surface with a
vertical wall or a fold is refused with a one-line error.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...geometry.surface import Surface

__all__ = ["SurfaceSamples", "sample_surface"]


@dataclass(frozen=True)
class SurfaceSamples:
    """Per-sample arrays, all (N,): parameters, position, graph derivatives, XY area.

    ``spacing`` is the largest XY distance between neighbouring samples (mm).
    """

    u: np.ndarray
    v: np.ndarray
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    p: np.ndarray
    q: np.ndarray
    hxx: np.ndarray
    hxy: np.ndarray
    hyy: np.ndarray
    area_xy: np.ndarray
    spacing: float

    def __len__(self) -> int:
        return len(self.u)

    def take(self, index) -> "SurfaceSamples":
        """The samples selected by a boolean mask or an index array."""
        f = {k: getattr(self, k)[index] for k in
             ("u", "v", "x", "y", "z", "p", "q", "hxx", "hxy", "hyy", "area_xy")}
        return SurfaceSamples(**f, spacing=self.spacing)

    @property
    def slope(self) -> np.ndarray:
        """Slope angle S = arccos(n_z) = arctan |grad z| (radians)."""
        return np.arctan(np.hypot(self.p, self.q))

    @property
    def steepest(self) -> np.ndarray:
        """Steepest-slope direction phi in [0, pi) (axial: uphill and downhill are one feed)."""
        return np.mod(np.arctan2(self.q, self.p), np.pi)

    def cell(self, n: int, m: int) -> np.ndarray:
        """Flat index i * m + j of the (n, m) parametric mesh cell holding each sample."""
        i = np.minimum((self.u * n).astype(np.int64), n - 1)
        j = np.minimum((self.v * m).astype(np.int64), m - 1)
        return i * m + j


def graph_derivatives(jet):
    """(p, q, hxx, hxy, hyy, detJ) of the graph z(x, y) from a parametric order-2 jet."""
    xu, yu, zu = jet.su.T
    xv, yv, zv = jet.sv.T
    det = xu * yv - xv * yu
    # J^-1 = [[yv, -xv], [-yu, xu]] / det ; (p, q) = J^-T (zu, zv)
    p = (yv * zu - yu * zv) / det
    q = (-xv * zu + xu * zv) / det
    a = jet.suu.T
    b = jet.suv.T
    c = jet.svv.T
    # K = Z_uv - p X_uv - q Y_uv (symmetric 2x2: k11, k12, k22)
    k11 = a[2] - p * a[0] - q * a[1]
    k12 = b[2] - p * b[0] - q * b[1]
    k22 = c[2] - p * c[0] - q * c[1]
    # H = Ji^T K Ji with Ji = J^-1 (columns: d(u, v)/dx, d(u, v)/dy)
    ux, vx = yv / det, -yu / det
    uy, vy = -xv / det, xu / det
    hxx = ux * ux * k11 + 2 * ux * vx * k12 + vx * vx * k22
    hxy = ux * uy * k11 + (ux * vy + vx * uy) * k12 + vx * vy * k22
    hyy = uy * uy * k11 + 2 * uy * vy * k12 + vy * vy * k22
    return p, q, hxx, hxy, hyy, det


def sample_surface(surface: Surface, spacing: float = 0.25, max_per_axis: int = 600,
                   min_per_axis: int = 16) -> SurfaceSamples:
    """Sample the surface at (u, v) cell centres about ``spacing`` mm apart in XY.

    The count per parameter direction is the longest XY length of the iso-curves divided by
    ``spacing``, clipped to [min_per_axis, max_per_axis].
    """
    t = np.linspace(0.0, 1.0, 33)
    uu, vv = np.meshgrid(t, t, indexing="ij")
    pts = surface.jet(uu.ravel(), vv.ravel(), order=0).p[:, :2].reshape(33, 33, 2)
    len_u = np.linalg.norm(np.diff(pts, axis=0), axis=-1).sum(axis=0).max()
    len_v = np.linalg.norm(np.diff(pts, axis=1), axis=-1).sum(axis=1).max()
    nu = int(np.clip(np.ceil(len_u / spacing), min_per_axis, max_per_axis))
    nv = int(np.clip(np.ceil(len_v / spacing), min_per_axis, max_per_axis))
    cu = (np.arange(nu) + 0.5) / nu
    cv = (np.arange(nv) + 0.5) / nv
    u, v = (a.ravel() for a in np.meshgrid(cu, cv, indexing="ij"))
    jet = surface.jet(u, v, order=2)
    p, q, hxx, hxy, hyy, det = graph_derivatives(jet)
    if not np.all(np.isfinite(det)) or np.any(det == 0) or (det.min() < 0 < det.max()):
        raise ValueError(
            f"surface: {getattr(surface, 'name', 'surface')} is not a graph over XY "
            "(the map (u, v) -> (x, y) folds or degenerates); zoning needs z = f(x, y)")
    x, y, z = jet.p.T
    area = np.abs(det) / (nu * nv)
    step_u = np.linalg.norm(jet.su[:, :2], axis=1).max() / nu
    step_v = np.linalg.norm(jet.sv[:, :2], axis=1).max() / nv
    return SurfaceSamples(u, v, x, y, z, p, q, hxx, hxy, hyy, area, float(max(step_u, step_v)))
