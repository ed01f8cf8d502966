"""STEP / IGES faces: an exact round trip through OCCT, units from the file, the face rule,
and every bad input as one line naming the file (and the face)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from tests.problems.toolpath.cad_parts import face_of, nurbs_face_surface
from tests.test_cli import evoplan, write

from evoplan.errors import EvoplanError
from evoplan.problems.toolpath.geometry.cad_faces import write_cad
from evoplan.problems.toolpath.geometry.spec import parse_surface


def occ_points(geom, bounds, u, v):
    """Points of an OCCT surface at the unit-square parameters (u, v) mapped to ``bounds``."""
    u0, u1, v0, v1 = bounds
    return np.array([geom.Value(u0 + a * (u1 - u0), v0 + b * (v1 - v0)).Coord()
                     for a, b in zip(u, v)])


def grid(n=17):
    t = np.linspace(0.0, 1.0, n)
    u, v = np.meshgrid(t, t, indexing="ij")
    return u.ravel(), v.ravel()


# IGES writes its reals with fewer digits than STEP: ~2e-9 mm on this 60 mm face
@pytest.mark.parametrize("kind, suffix, tol", [("step", "step", 1e-9), ("iges", "igs", 1e-8)])
def test_a_nurbs_face_written_with_occt_reads_back_to_the_same_points(tmp_path, kind, suffix,
                                                                      tol):
    geom = nurbs_face_surface()
    path = tmp_path / f"face.{suffix}"
    write_cad(face_of(geom), path, kind)
    surf = parse_surface({"type": kind, "file": str(path)})
    u, v = grid()
    want = occ_points(geom, (2.0, 5.0, -1.0, 3.0), u, v)
    assert np.abs(surf.points(u, v) - want).max() < tol
    # the untrimmed face's domain is its whole parameter rectangle
    assert surf.footprint.contains(u, v).all() and surf.footprint.area() == pytest.approx(1.0)
    assert surf.normals([0.5], [0.5])[0, 2] > 0


def test_lengths_come_in_mm_whatever_the_file_unit(tmp_path):
    geom = nurbs_face_surface(1)
    u, v = grid(9)
    pts = {}
    for unit in ("MM", "M", "IN"):
        write_cad(face_of(geom), tmp_path / f"{unit}.step", "step", unit)
        surf = parse_surface({"type": "step", "file": str(tmp_path / f"{unit}.step")})
        pts[unit] = surf.points(u, v)
        assert surf.source["unit"] != "?"
    # the same shape written in metres or inches is scaled back to the same mm
    assert np.abs(pts["M"] - pts["MM"]).max() < 1e-7
    assert np.abs(pts["IN"] - pts["MM"]).max() < 1e-7


def box_file(tmp_path):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox

    path = tmp_path / "box.step"
    write_cad(BRepPrimAPI_MakeBox(40.0, 30.0, 10.0).Shape(), path)
    return path


def test_largest_picks_the_biggest_face_machinable_from_above(tmp_path):
    surf = parse_surface({"type": "step", "file": str(box_file(tmp_path)), "face": "largest"})
    u, v = grid(5)
    p = surf.points(u, v)
    # the top (z = 10), not the bottom of equal area (its material side faces down)
    assert np.allclose(p[:, 2], 10.0) and np.ptp(p[:, 0]) == pytest.approx(40.0)
    assert np.allclose(surf.normals(u, v), (0, 0, 1))


def no_face_file(tmp_path):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.gp import gp_Pnt

    path = tmp_path / "vertex.step"
    write_cad(BRepBuilderAPI_MakeVertex(gp_Pnt(1, 2, 3)).Vertex(), path)
    return path


def bad_cases(tmp_path):
    """case -> (surface settings, the start of the expected line)."""
    box = box_file(tmp_path)
    empty = tmp_path / "empty.step"
    empty.write_bytes(b"")
    junk = tmp_path / "junk.step"
    junk.write_text("ISO-10303-21;\nHEADER;\nthis is not STEP\n")
    igs = tmp_path / "junk.igs"
    igs.write_text("not an IGES file at all\n")
    return {
        "empty": ({"type": "step", "file": str(empty)}, f"surface.file: {empty}: the file is empty"),
        "corrupt": ({"type": "step", "file": str(junk)}, f"surface.file: {junk}: not a readable STEP"),
        "corrupt_iges": ({"type": "iges", "file": str(igs)}, f"surface.file: {igs}: "),
        "no_face": ({"type": "step", "file": str(no_face_file(tmp_path))},
                    "surface.file: ", "holds no face"),
        "missing_file": ({"type": "step", "file": str(tmp_path / "nope.step")},
                         "surface.file: file not found"),
        "out_of_range": ({"type": "step", "file": str(box), "face": 6},
                         "surface.face: 6 is out of range: box.step holds 6 faces (0..5)"),
        "several": ({"type": "step", "file": str(box)},
                    "surface.face: box.step holds 6 faces: give face: an index 0..5 or largest"),
        "wall": ({"type": "step", "file": str(box), "face": 0},
                 "surface.face: box.step, face 0 is not a height field over XY: its material "
                 "side is vertical", "near x="),
        "bottom": ({"type": "step", "file": str(box), "face": 4},
                   "surface.face: box.step, face 4 is not a height field over XY: its material "
                   "side faces down", "near x="),
        "face_type": ({"type": "step", "file": str(box), "face": 1.5},
                      "surface.face: expected a face index (0, 1, ...) or largest, got 1.5"),
    }


@pytest.mark.parametrize("case", ["empty", "corrupt", "corrupt_iges", "no_face", "missing_file",
                                  "out_of_range", "several", "wall", "bottom", "face_type"])
def test_bad_cad_input_is_one_line_naming_the_file(tmp_path, case):
    spec, start, *more = bad_cases(tmp_path)[case]
    with pytest.raises(ValueError) as err:
        parse_surface(spec)
    msg = str(err.value)
    assert msg.startswith(start) and "\n" not in msg, msg
    assert all(m in msg for m in more), msg


RUN = """
seed: 1
problem:
  name: toolpath
  params: {{surface: {{type: step, file: {file}{face}}}}}
algorithm: {{name: vega, population: 4, virus: {{count: 1}}}}
termination: {{generations: 1}}
"""


@pytest.mark.parametrize("case", ["corrupt", "several"])
def test_bad_cad_input_through_the_cli_is_exit_2_and_no_files(tmp_path, case):
    spec, start, *_ = bad_cases(tmp_path)[case]
    face = f", face: {spec['face']}" if "face" in spec else ""
    cfg = write(tmp_path / "t.yaml", RUN.format(file=spec["file"], face=face))
    proc = evoplan("run", cfg, "--out", tmp_path / "res")
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and start in lines[0] and str(cfg) in lines[0], proc.stderr
    assert not (tmp_path / "res").exists()


def test_a_missing_cad_extra_is_one_line_naming_it(tmp_path, monkeypatch):
    path = box_file(tmp_path)
    monkeypatch.setitem(sys.modules, "OCP", None)  # import OCP now fails
    with pytest.raises(EvoplanError) as err:
        parse_surface({"type": "step", "file": str(path), "face": 0})
    assert "evoplan[cad]" in str(err.value) and "\n" not in str(err.value)


def test_a_ball_plan_on_a_step_cylinder_leaves_the_circle_intersection_cusp(tmp_path):
    """A cylinder face (OCCT's Geom_CylindricalSurface, axis X, radius 30, 44 deg of arc)
    written as STEP and read back (rational, exact); a 3-axis ball plan (D8) along the axis,
    simulated on a 0.05 mm grid: every cell between the passes is left at the closed form,
    the upper envelope of the ball circles of radius r about the centres on the offset
    cylinder (their cusp is where two circles intersect), to 2e-5 mm as the NURBS cylinder
    test (test_nurbs_surface.py) holds its cusp."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_CylindricalSurface
    from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt

    from evoplan.problems.toolpath.plan.planner import Planner
    from evoplan.problems.toolpath.simulation import design_grid, sweep_path
    from evoplan.problems.toolpath.spec import parse_tools

    rho, r, length, half = 30.0, 4.0, 20.0, np.radians(22.0)
    cyl = Geom_CylindricalSurface(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), gp_Dir(0, 1, 0)), rho)
    face = BRepBuilderAPI_MakeFace(cyl, np.pi / 2 - half, np.pi / 2 + half, 0.0, length,
                                   1e-7).Face()
    write_cad(face, tmp_path / "cylinder.step")
    surf = parse_surface({"type": "step", "file": str(tmp_path / "cylinder.step")})
    u, v = grid(9)
    p = surf.points(u, v)
    assert np.abs(np.hypot(p[:, 1], p[:, 2]) - rho).max() < 1e-9
    planner = Planner(surf, parse_tools([{"id": 1, "type": "ball", "diameter": 2 * r}]),
                      machine="3axis", tolerance=0.005)
    path = planner.cl_path({"tool": [0], "stepover": [30.0], "step": [5.0]})
    centre = path.tip + (0.0, 0.0, r)
    d = rho + r
    assert np.abs(np.hypot(centre[:, 1], centre[:, 2]) - d).max() < 1e-9  # tangent balls
    phi = np.unique(np.round(np.arctan2(centre[:, 1], centre[:, 2]), 9))  # one per pass
    assert len(phi) >= 8
    g = design_grid(surf, 0.05)
    res = sweep_path(path, g).values
    x, y = np.meshgrid(g.xs, g.ys)
    theta = np.arctan2(y, g.z)  # each cell's angle about the axis (its ray is radial)
    off = theta[..., None] - phi
    disc = r * r - (d * np.sin(off)) ** 2
    reach = np.where(disc >= 0, d * np.cos(off) - np.sqrt(np.abs(disc)), np.inf)
    want = reach.min(axis=-1) - rho  # the lowest ball surface along each ray
    keep = g.inside & (x > 3) & (x < length - 3) & (theta > phi[1]) & (theta < phi[-2])
    assert keep.sum() > 50000
    assert np.abs(res - want)[keep].max() < 2e-5
    gaps = np.diff(phi[1:-1])
    cusps = d * np.cos(gaps / 2) - np.sqrt(r * r - (d * np.sin(gaps / 2)) ** 2) - rho
    assert res[keep].max() <= cusps.max() + 2e-5 and res[keep].max() > 0.9 * cusps.max()
