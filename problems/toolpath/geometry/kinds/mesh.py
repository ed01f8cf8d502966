"""``type: mesh``: a part given as an STL, OBJ or PLY triangle mesh (trimesh, the ``mesh`` extra).

Keys: ``file`` (relative to the run file's folder), ``units`` (of the file's numbers: mm
default, cm, m, um, in), ``max_deviation`` (mm, default 0.005: the smooth fit the planner
uses may depart from the mesh by at most this much, else the surface is refused) and
``fit_spacing`` (mm between the fit's knots; default three median edge lengths) and
``facing`` (``all``, the default: the mesh is the surface; ``up``: the mesh is a closed solid
and its upward-facing triangles are the surface). The surface must be a height field over XY
(``mesh_io.py``); the cut simulation measures against the mesh itself (``mesh_surface.py``).

A built mesh is kept for the process (keyed by the file's path, size and modification time
and the settings), so a command that reads the surface twice loads and fits it once.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import PositiveFloat, StrictStr

from ..mesh_fit import deviation, fit_height_field
from ..mesh_io import UNITS, read_mesh
from ..mesh_surface import MeshSurface
from ..nets import resolve
from ..registry import SurfaceSettings, register

__all__ = ["MeshSettings"]

MAX_DEVIATION_MM = 0.005
_CACHE: dict[tuple, tuple] = {}
_CACHE_SIZE = 4


@register
class MeshSettings(SurfaceSettings):
    """``file`` required; ``units``, ``max_deviation``, ``fit_spacing``, ``facing`` optional."""

    check_graph = False  # the mesh itself is checked (mesh_io.py), not the fit

    type: Literal["mesh"] = "mesh"
    file: StrictStr
    units: Literal[tuple(UNITS)] = "mm"
    max_deviation: PositiveFloat = MAX_DEVIATION_MM
    fit_spacing: PositiveFloat | None = None
    facing: Literal["all", "up"] = "all"

    def build(self, key: str, base_dir=None) -> MeshSurface:
        fkey = f"{key}.file"
        path = resolve(self.file, fkey, base_dir)
        stat = path.stat()
        ident = (str(path.resolve()), stat.st_size, stat.st_mtime_ns, self.units, self.fit_spacing,
                 self.facing)
        if ident not in _CACHE:
            mesh = read_mesh(path, fkey, units=self.units, label=self.file, facing=self.facing)
            fit = fit_height_field(mesh, self.fit_spacing, fkey)
            if len(_CACHE) >= _CACHE_SIZE:
                _CACHE.pop(next(iter(_CACHE)))
            _CACHE[ident] = (mesh, fit, deviation(fit, mesh))
        mesh, fit, dev = _CACHE[ident]
        if dev.max_mm > self.max_deviation:
            x, y = dev.where
            raise ValueError(
                f"{fkey}: {self.file}: the fit is {dev.max_mm:.4g} mm off the mesh at (x, y) = "
                f"({x:.2f}, {y:.2f}), above max_deviation {self.max_deviation:g} mm (finer mesh? "
                f"fit_spacing below {fit.spacing:.3g} mm?)")
        facts = {"type": "mesh", "file": Path(self.file).name, "units": self.units,
                 "facing": self.facing,
                 "triangles": int(len(mesh.faces)), "vertices": int(len(mesh.vertices)),
                 "degenerate_dropped": mesh.dropped,
                 "fit": {"kind": "bicubic B-spline height field, least squares",
                         "spacing_mm": round(fit.spacing, 6),
                         "coefficients": list(fit.surface.coeffs.shape),
                         "max_deviation_mm": dev.max_mm, "rms_deviation_mm": dev.rms_mm,
                         "max_deviation_at_xy": [round(c, 4) for c in dev.where],
                         "measured_points": dev.points, "limit_mm": self.max_deviation}}
        return MeshSurface(mesh, fit, dev, facts)
