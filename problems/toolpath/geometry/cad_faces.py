"""Faces of STEP and IGES files, read through OCCT (``cadquery-ocp``, the ``cad`` extra).

A CAD face is a surface S(s, t) over a parameter rectangle, trimmed by wires: only the part
inside its outer wire and outside its inner wires (holes) is material. Here a face becomes

- its exact NURBS: a B-spline, Bezier or plane face through ``GeomConvert`` (its
  parameters unchanged), any other face rebuilt by ``BRepBuilderAPI_NurbsConvert`` (a
  cylinder, cone, sphere, torus, revolved or extruded surface becomes a rational B-spline
  with the same points, its trimming curves mapped to the new parameters), segmented to the face's parameter bounds
  (``BRepTools.UVBounds``) so that the unit square the engine sees is the smallest one that
  holds the trimmed face: poles, weights, degrees and clamped knot vectors, the input of
  :class:`~.nurbs.NURBSSurface`;
- its trimmed domain: every wire walked edge by edge in order (``BRepTools_WireExplorer``),
  each edge's curve on the face (its pcurve) sampled where the 3-D curve on the surface
  turns by more than ``ANGULAR`` radians or sags by more than ``DEFLECTION`` mm from its chord
  (``GCPnts_TangentialDeflection``), mapped to the unit square: the outer wire first
  (``BRepTools.OuterWire``), then the holes.

Lengths: OCCT scales a file's geometry to millimetres on transfer (the reader's system length
unit, set to 1 mm here); the file's own unit name is kept for the record.

Every call takes the ``key`` of the setting it serves, and every error is one ``ValueError``
line naming the file (and the face).
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["CadFile", "read_cad", "FaceNurbs", "face_nurbs", "ANGULAR", "DEFLECTION"]

ANGULAR = 0.1  # rad: largest turn of a trimming edge between two samples
DEFLECTION = 1e-3  # mm: largest sag of a trimming edge from its chords
FORMATS = {"step": "STEP", "iges": "IGES"}


def occ():
    """The OCP package, or one line naming the ``cad`` extra."""
    from evoplan.extras import require

    return require("OCP", "cad", "a STEP or IGES surface")


@contextlib.contextmanager
def quiet():
    """OCCT's default messenger silenced (its readers and writers print to the terminal)."""
    from OCP.Message import Message

    messenger = Message.DefaultMessenger_s()
    printers = list(messenger.Printers())
    for p in printers:
        messenger.RemovePrinter(p)
    try:
        yield
    finally:
        for p in printers:
            messenger.AddPrinter(p)


@dataclass
class CadFile:
    """A read file: its ``path``, ``kind`` (step | iges), the ``faces`` (TopoDS_Face, in the
    order of a ``TopExp_Explorer`` over the shape), ``solid`` (the faces bound a solid: their
    orientation says which side is outside) and the file's length ``unit`` name."""

    path: Path
    kind: str
    faces: list
    solid: bool
    unit: str

    def where(self, index: int | None = None) -> str:
        """``file`` or ``file, face i``: how error lines name the place."""
        return f"{self.path.name}" if index is None else f"{self.path.name}, face {index}"


def read_cad(path: Path, kind: str, key: str) -> CadFile:
    """Read a STEP or IGES file; one line naming it when it is empty, corrupt, crashes OCCT's
    reader or has no face."""
    occ()
    from OCP.TopAbs import TopAbs_FACE, TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    name = FORMATS[kind]
    if path.stat().st_size == 0:
        raise ValueError(f"{key}: {path}: the file is empty, not a {name} file")
    crash = _crash_signal(lambda: _read_shape(path, kind, key))
    if crash is not None:
        raise ValueError(f"{key}: {path}: OCCT's {name} reader crashed on the file ({crash}): "
                         f"it is damaged or not a {name} file")
    shape, unit = _read_shape(path, kind, key)
    faces = []
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        faces.append(TopoDS.Face(exp.Current()))
        exp.Next()
    if not faces:
        raise ValueError(f"{key}: {path}: the {name} file holds no face")
    solid = TopExp_Explorer(shape, TopAbs_SOLID).More()
    return CadFile(path, kind, faces, solid, unit)


def _crash_signal(read) -> str | None:
    """Run ``read`` in a forked child first: OCCT's readers dereference damaged records and end
    the process with SIGSEGV, which no ``except`` can catch. The name of the signal that killed
    the child, or None when it came back (its errors, if any, are raised again by the caller's
    own read). The file is thus read twice: the shapes cannot be sent back from the child. It
    shares the parent's imports, so for the 174 kB sample part the forked read takes 0.034 s
    against 0.018 s in-process. Where there is no ``fork`` (Windows), it is unsafe (macOS) or it
    fails (no process left to the user), the file is read unprobed."""
    import faulthandler
    import os
    import signal
    import sys

    if not sys.platform.startswith("linux"):
        return None
    try:
        pid = os.fork()
    except OSError:
        return None
    if pid == 0:  # the child: quiet, and out without running the parent's exit handlers
        try:
            faulthandler.disable()  # its crash report would reach the parent's terminal
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.dup2(devnull, 2)
            read()
        except BaseException:  # noqa: BLE001 - the parent reads again and reports it
            pass
        os._exit(0)
    _, status = os.waitpid(pid, 0)
    if os.WIFSIGNALED(status):
        return signal.Signals(os.WTERMSIG(status)).name
    return None


def _read_shape(path: Path, kind: str, key: str):
    """The file's shape (transferred in mm) and its length unit's name; one line when OCCT
    refuses it."""
    from OCP.IFSelect import IFSelect_RetDone

    name = FORMATS[kind]
    with quiet():
        if kind == "step":
            from OCP.STEPControl import STEPControl_Reader

            reader = STEPControl_Reader()
        else:
            from OCP.IGESControl import IGESControl_Reader

            reader = IGESControl_Reader()
        try:
            status = reader.ReadFile(str(path))
        except Exception as exc:  # OCCT raises Standard_Failure on some malformed files
            raise ValueError(f"{key}: {path}: not a readable {name} file ({exc})") from None
        if status != IFSelect_RetDone:
            raise ValueError(f"{key}: {path}: not a readable {name} file "
                             f"(OCCT: {str(status).rsplit('_', 1)[-1]})")
        if kind == "step":
            reader.SetSystemLengthUnit(1.0)  # transfer in mm
        try:
            reader.TransferRoots()
            shape = reader.OneShape()
        except Exception as exc:
            raise ValueError(f"{key}: {path}: OCCT could not build its shapes ({exc})") from None
        unit = _unit_name(reader, kind)
    return shape, unit


def _unit_name(reader, kind: str) -> str:
    """The file's length unit as it names it (``MM``, ``INCH``, ...), or ``?``."""
    try:
        if kind == "step":
            from OCP.OCP.collections import Sequence_TCollection_AsciiString as Names

            length, angle, solid = Names(), Names(), Names()
            reader.FileUnits(length, angle, solid)
            names = sorted({length.Value(i).ToCString() for i in range(1, length.Size() + 1)})
            return ", ".join(names) or "?"
        return reader.IGESModel().GlobalSection().UnitName().ToCString() or "?"
    except Exception:  # the unit is informative only
        return "?"


def face_area(face) -> float:
    """Area (mm^2) of a trimmed face (``BRepGProp``)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, props)
    return float(props.Mass())


@dataclass
class FaceNurbs:
    """A face as a NURBS over the unit square: ``poles`` (nu, nv, 3), ``weights`` (nu, nv),
    ``degree`` (p, q), full knot vectors, the trimming ``loops`` in the unit square (outer
    first) and ``reversed`` (the face's material side is opposite to S_u x S_v)."""

    poles: np.ndarray
    weights: np.ndarray
    degree: tuple[int, int]
    knots_u: np.ndarray
    knots_v: np.ndarray
    loops: list[np.ndarray]
    reversed: bool


def face_nurbs(face, where: str, key: str) -> FaceNurbs:
    """The exact NURBS of a trimmed face and its trimmed domain (see the module docstring)."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
    from OCP.BRepTools import BRepTools
    from OCP.Geom import Geom_BSplineSurface, Geom_RectangularTrimmedSurface
    from OCP.GeomConvert import GeomConvert
    from OCP.TopAbs import TopAbs_REVERSED
    from OCP.TopoDS import TopoDS

    _same_parameters()

    try:
        with quiet():
            surf = BRep_Tool.Surface_s(face)
            if isinstance(surf, _SAME_PARAMETERS):  # its B-spline has the face's parameters
                nface = face
                u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
                surf = GeomConvert.SurfaceToBSplineSurface_s(
                    Geom_RectangularTrimmedSurface(surf, u0, u1, v0, v1))
            else:  # reparametrized: the face rebuilt on its NURBS, pcurves included
                nface = TopoDS.Face(BRepBuilderAPI_NurbsConvert(face, True).Shape())
                surf = BRep_Tool.Surface_s(nface)
                u0, u1, v0, v1 = BRepTools.UVBounds_s(nface)
            if not isinstance(surf, Geom_BSplineSurface):
                raise TypeError(f"converted to {surf.DynamicType().Name()}, not a B-spline")
            bs = surf.Copy()
            if bs.IsUPeriodic():
                bs.SetUNotPeriodic()
            if bs.IsVPeriodic():
                bs.SetVNotPeriodic()
            lo_u, hi_u, lo_v, hi_v = bs.Bounds()
            if u0 > lo_u + 1e-12 or u1 < hi_u - 1e-12 or v0 > lo_v + 1e-12 or v1 < hi_v - 1e-12:
                bs.Segment(u0, u1, v0, v1)
            u0, u1, v0, v1 = bs.Bounds()
            loops = _loops(nface, (u0, u1, v0, v1))
    except ValueError:
        raise
    except Exception as exc:
        raise ValueError(f"{key}: {where}: OCCT could not convert the face to a NURBS "
                         f"({exc})") from None
    nu, nv = bs.NbUPoles(), bs.NbVPoles()
    poles = np.array([[bs.Pole(i, j).Coord() for j in range(1, nv + 1)]
                      for i in range(1, nu + 1)], float)
    weights = np.array([[bs.Weight(i, j) for j in range(1, nv + 1)]
                        for i in range(1, nu + 1)], float)
    ku, kv = bs.UKnotSequence(), bs.VKnotSequence()
    knots_u = np.array([ku.Value(i) for i in range(ku.Lower(), ku.Upper() + 1)])
    knots_v = np.array([kv.Value(i) for i in range(kv.Lower(), kv.Upper() + 1)])
    return FaceNurbs(poles, weights, (bs.UDegree(), bs.VDegree()), knots_u, knots_v, loops,
                     face.Orientation() == TopAbs_REVERSED)


_SAME_PARAMETERS: tuple = ()


def _same_parameters():
    """The surface types whose B-spline (``GeomConvert``) keeps their parameters: B-spline,
    Bezier and plane (affine). Their faces skip ``BRepBuilderAPI_NurbsConvert``, which
    rebuilds every trimming curve (2.5 s on the sample part's top face)."""
    global _SAME_PARAMETERS
    if not _SAME_PARAMETERS:
        from OCP.Geom import Geom_BezierSurface, Geom_BSplineSurface, Geom_Plane

        _SAME_PARAMETERS = (Geom_BSplineSurface, Geom_BezierSurface, Geom_Plane)


def _loops(face, bounds) -> list[np.ndarray]:
    """The face's wires as closed polylines in the unit square, the outer wire first."""
    from OCP.BRepTools import BRepTools
    from OCP.TopAbs import TopAbs_WIRE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    outer = BRepTools.OuterWire_s(face)
    wires = []
    exp = TopExp_Explorer(face, TopAbs_WIRE)
    while exp.More():
        w = TopoDS.Wire(exp.Current())
        (wires.insert(0, w) if w.IsSame(outer) else wires.append(w))
        exp.Next()
    u0, u1, v0, v1 = bounds
    scale = np.array([u1 - u0, v1 - v0])
    origin = np.array([u0, v0])
    loops = []
    for w in wires:
        uv = _wire_uv(w, face)
        if len(uv) >= 3:
            loops.append((uv - origin) / scale)
    return loops


def _wire_uv(wire, face) -> np.ndarray:
    """(k, 2) parameter points along a wire in order, each edge's end left to the next."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Curve2d
    from OCP.BRepTools import BRepTools_WireExplorer
    from OCP.GCPnts import GCPnts_TangentialDeflection
    from OCP.TopAbs import TopAbs_REVERSED

    pts = []
    exp = BRepTools_WireExplorer(wire, face)
    while exp.More():
        edge = exp.Current()
        pc = BRepAdaptor_Curve2d(edge, face)
        a, b = pc.FirstParameter(), pc.LastParameter()
        if BRep_Tool.Degenerated_s(edge):
            t = np.array([a, b])
        else:
            sampler = GCPnts_TangentialDeflection(BRepAdaptor_Curve(edge, face), a, b,
                                                  ANGULAR, DEFLECTION, 2)
            t = np.array([sampler.Parameter(i) for i in range(1, sampler.NbPoints() + 1)])
        if edge.Orientation() == TopAbs_REVERSED:
            t = t[::-1]
        pts.extend(pc.Value(x).Coord() for x in t[:-1])
        exp.Next()
    return np.asarray(pts, float).reshape(-1, 2)


def write_cad(shape, path: Path, kind: str = "step", unit: str = "MM") -> None:
    """Write an OCCT shape as a STEP or IGES file in ``unit`` (``MM``, ``M``, ``IN``, ...):
    the sample parts' script and the tests make their files with it."""
    occ()
    from OCP.Interface import Interface_Static

    with quiet():
        if kind == "step":
            from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

            writer = STEPControl_Writer()  # registers the write.step.* parameters
            Interface_Static.SetCVal_s("write.step.unit", unit)
            writer.Transfer(shape, STEPControl_AsIs)
            ok = writer.Write(str(path))
            from OCP.IFSelect import IFSelect_RetDone

            ok = ok == IFSelect_RetDone
        else:
            from OCP.IGESControl import IGESControl_Writer

            writer = IGESControl_Writer(unit, 0)
            writer.AddShape(shape)
            writer.ComputeModel()
            ok = writer.Write(str(path))
    if not ok:
        raise OSError(f"OCCT could not write {path}")
