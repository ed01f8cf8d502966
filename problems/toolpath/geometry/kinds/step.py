"""``type: step`` / ``type: iges``: one face of a CAD file, exact, trimmed (the ``cad`` extra).

Keys: ``file`` (the path, relative to the run file's folder) and ``face``: which face, by its
index in the file (0-based, in OCCT's order of the faces), or ``largest``: the face of
largest area among those machinable from above (the rule of ``cad_surface``: its material
side faces up, n_z > sin 1 deg, over its whole trimmed domain). ``face`` may be left out
only when the file holds one face.

The face is read through OCCT (``cad_faces.py``) and becomes a :class:`NURBSSurface` over the
unit square (exact: a plane, cylinder or sphere stays one) whose ``footprint`` is the face's
trimmed domain, outer wire and holes. Its tool side is the outside of the solid when the
faces bound one (the face's orientation), else the side with +z at the domain centre.
Lengths are in millimetres (OCCT converts the file's unit on reading).
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal, Union

import numpy as np
from pydantic import StrictStr, field_validator

from ..cad_faces import CadFile, face_area, face_nurbs, read_cad
from ..footprint import UNIT_SQUARE, Footprint
from ..nets import resolve
from ..nurbs import NURBSSurface
from ..registry import SurfaceSettings, register
from ..surface import unit_normal

__all__ = ["StepSettings", "IgesSettings", "cad_surface", "face_surface"]

MIN_NZ = np.sin(np.radians(1.0))  # the steepest accepted wall: 89 degrees (surface_checks)


class CadFaceSettings(SurfaceSettings):
    """``file`` (path) and ``face`` (index or ``largest``)."""

    check_graph = False  # checked over the trimmed domain only (cad_surface)

    file: StrictStr
    face: Union[int, str, None] = None

    @field_validator("face", mode="before")
    @classmethod
    def _face(cls, value):
        ok = value is None or value == "largest" or (
            isinstance(value, int) and not isinstance(value, bool))
        if not ok:
            raise ValueError(f"expected a face index (0, 1, ...) or largest, got {value!r}")
        return value

    def build(self, key: str, base_dir=None):
        path = resolve(self.file, f"{key}.file", base_dir)
        return cad_surface(path, self.type, self.face, key)


@register
class StepSettings(CadFaceSettings):
    type: Literal["step"] = "step"


@register
class IgesSettings(CadFaceSettings):
    type: Literal["iges"] = "iges"


def cad_surface(path: Path, kind: str, face, key: str = "surface") -> NURBSSurface:
    """Face ``face`` (index, ``"largest"`` or None for a one-face file) of a CAD file."""
    cad = read_cad(Path(path), kind, f"{key}.file")
    n = len(cad.faces)
    if face is None:
        if n > 1:
            raise ValueError(f"{key}.face: {cad.where()} holds {n} faces: give face: an index "
                             f"0..{n - 1} or largest")
        face = 0
    if face == "largest":
        order = np.argsort([-face_area(f) for f in cad.faces], kind="stable")
        for i in order:
            surf, problem = face_surface(cad, int(i), key)
            if problem is None:
                return surf
        raise ValueError(f"{key}.face: no face of {cad.where()} is machinable from above "
                         f"(a height field over XY with its material side up)")
    if not 0 <= face < n:
        raise ValueError(f"{key}.face: {face} is out of range: {cad.where()} holds {n} "
                         f"face{'s' if n > 1 else ''} (0..{n - 1})")
    surf, problem = face_surface(cad, face, key)
    if problem is not None:
        raise ValueError(f"{key}.face: {cad.where(face)} is not a height field over XY: "
                         f"{problem}; the toolpath model needs a face machinable from above")
    return surf


def face_surface(cad: CadFile, index: int, key: str) -> tuple[NURBSSurface, str | None]:
    """(surface, why it is not machinable from above or None) of face ``index``."""
    where = cad.where(index)
    fn = face_nurbs(cad.faces[index], where, key)
    if not fn.loops:
        raise ValueError(f"{key}.face: {where} has no trimming wire")
    name = f"{cad.kind}:{cad.path.name}#{index}"
    surf = NURBSSurface(fn.poles, fn.weights, fn.degree, fn.knots_u, fn.knots_v, name=name)
    if cad.solid:
        surf.normal_sign = -1.0 if fn.reversed else 1.0
    fp = Footprint(fn.loops, sampled=True)  # within cad_faces.DEFLECTION
    lo, hi = fn.loops[0].min(axis=0), fn.loops[0].max(axis=0)
    untrimmed = (len(fn.loops) == 1 and abs(fp.area() - 1.0) < 1e-9
                 and np.allclose(lo, 0.0, atol=1e-9) and np.allclose(hi, 1.0, atol=1e-9))
    surf.footprint = UNIT_SQUARE if untrimmed else fp  # an untrimmed face: the whole square
    surf.source = {"file": str(cad.path), "face": index, "unit": cad.unit}
    return surf, height_field_problem(surf)


def height_field_problem(surface, n: int = 81) -> str | None:
    """Why the trimmed face is not machinable from above (normal on the tool side with
    n_z <= sin 1 deg somewhere in its footprint: a vertical wall, a fold or an overhang, or
    the material side facing down), naming the worst point; None if it is."""
    t = np.linspace(0.0, 1.0, n)
    u, v = (a.ravel() for a in np.meshgrid(t, t, indexing="ij"))
    keep = surface.footprint.contains(u, v)
    extra = [lp for lp in surface.footprint.loops]  # the trimming wires themselves
    u = np.concatenate([u[keep]] + [lp[:, 0] for lp in extra])
    v = np.concatenate([v[keep]] + [lp[:, 1] for lp in extra])
    jet = surface.jet(u, v, order=1)
    with np.errstate(invalid="ignore", divide="ignore"):  # a collapsed edge: no normal
        nz = np.nan_to_num(unit_normal(jet, surface.normal_sign)[:, 2], nan=1.0)
    worst = int(np.argmin(nz))
    if nz[worst] > MIN_NZ:
        return None
    x, y, z = jet.p[worst]
    what = "faces down" if nz[worst] < -MIN_NZ else "is vertical"
    return (f"its material side {what} (normal z {nz[worst]:.2f}) near "
            f"x={x:.2f}, y={y:.2f}, z={z:.2f} mm")
