"""A part given as a triangle mesh: planned on a smooth fit, simulated against the mesh itself.

:class:`MeshSurface` is the height field fitted to the mesh (``mesh_fit.py``): every jet
the planner, the criteria and the drop-cutter ask for comes from the fit (smooth normals and
curvatures, which a faceted mesh does not have). Its largest deviation from the mesh is
measured when it is built and recorded in :meth:`MeshSurface.facts`, which every command
writes into its output. The cut simulation does not use the fit: :meth:`design_cells` gives
the simulation grid the mesh's own heights (the triangle over each cell centre) and facet
normals, so every simulated number is measured against the mesh.

The footprint is the whole parameter square when the mesh covers its XY bounding rectangle;
otherwise it is the mesh's boundary loops mapped to (u, v) (the one enclosing the largest
area is the outer loop, the others holes).
"""

from __future__ import annotations

import numpy as np

from .footprint import UNIT_SQUARE, Footprint
from .heightfield import HeightFieldSurface
from .mesh_fit import Deviation, Fit
from .mesh_io import TriangleMesh, boundary_loops
from .mesh_raster import rasterize

__all__ = ["MeshSurface"]


class MeshSurface(HeightFieldSurface):
    """The fit of ``mesh`` (a :class:`~.mesh_fit.Fit`) with its measured deviation."""

    def __init__(self, mesh: TriangleMesh, fit: Fit, deviation: Deviation, facts: dict):
        s = fit.surface
        super().__init__(s.knots, s.coeffs, s.bounds, name="mesh")
        self.mesh = mesh
        self.fit = fit
        self.deviation = deviation
        self._facts = facts
        self.footprint = _footprint(mesh, self.bounds)

    def facts(self) -> dict:
        """What an output records about this surface: the file, its size and the fit."""
        return dict(self._facts)

    def design_cells(self, x0: float, y0: float, h: float, nx: int, ny: int):
        """(z, normal, inside, u, v) of the simulation cells centred at (x0 + ix h, y0 + iy h)
        (``simulation/design.py``): the mesh's height and facet normal (tool side) over each
        centre; cells over no triangle are off the part."""
        r = rasterize(self.mesh, x0, y0, h, nx, ny)
        inside = r.face >= 0
        normal = np.zeros((ny, nx, 3))
        normal[..., 2] = 1.0
        normal[inside] = self.mesh.normals[r.face[inside]]
        normal *= self.normal_sign
        bx0, bx1, by0, by1 = self.bounds
        xs, ys = x0 + h * np.arange(nx), y0 + h * np.arange(ny)
        u = np.where(inside, ((xs - bx0) / (bx1 - bx0))[None, :], np.nan)
        v = np.where(inside, ((ys - by0) / (by1 - by0))[:, None], np.nan)
        return r.z, normal, inside, u, v


def _footprint(mesh: TriangleMesh, bounds) -> Footprint:
    """UNIT_SQUARE when the mesh covers its bounding rectangle, else its boundary loops."""
    x0, x1, y0, y1 = bounds
    v, f = mesh.vertices, mesh.faces
    a, b, c = (v[f[:, k], :2] for k in range(3))
    plan = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])).sum()
    box = (x1 - x0) * (y1 - y0)
    if plan >= box * (1.0 - 1e-9):
        return UNIT_SQUARE
    scale = np.array([x1 - x0, y1 - y0])
    loops = [(v[lp, :2] - (x0, y0)) / scale for lp in boundary_loops(mesh)]
    loops.sort(key=lambda p: -abs(np.dot(p[:, 0], np.roll(p[:, 1], -1))
                                  - np.dot(p[:, 1], np.roll(p[:, 0], -1))))
    return Footprint(loops)
