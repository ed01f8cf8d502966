"""Mesh surfaces (type: mesh): an STL of an analytic paraboloid against the exact surface.

The paraboloid z = 10 - ((x - 30)^2 + (y - 20)^2) / (2 Rc) is a biquadratic Bezier patch
exactly, so the same plan can be made and simulated on both. On a grid of squares of side s
split into right triangles, the linear interpolant's sag is at most s^2 / (4 Rc) (the
circumradius s / sqrt 2 squared over 2 Rc).
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
import pytest

from evoplan.problems.toolpath import ToolpathProblem
from evoplan.problems.toolpath.geometry.spec import parse_surface
from evoplan.problems.toolpath.simulation import design_grid, simulate

pytest.importorskip("trimesh")

ROOT = Path(__file__).resolve().parents[3]
PART = runpy.run_path(str(ROOT / "runs" / "parts" / "make_mesh_part.py"))
LX, LY, RC, S = 40.0, 30.0, 60.0, 0.8
SAG = S * S / (4 * RC)


def fz(x, y):
    return 10.0 - ((x - 20.0) ** 2 + (y - 15.0) ** 2) / (2 * RC)


def write_grid_stl(path: Path, f=fz, lx=LX, ly=LY, s=S) -> Path:
    xs = np.linspace(0.0, lx, int(round(lx / s)) + 1)
    ys = np.linspace(0.0, ly, int(round(ly / s)) + 1)
    X, Y = np.meshgrid(xs, ys)
    path.write_bytes(PART["stl_bytes"](PART["grid_triangles"](xs, ys, f(X, Y))))
    return path


def exact_surface():
    """The paraboloid as a biquadratic Bezier net: x = LX u, y = LY v."""
    def poles_1d(length, centre):
        f0, f1 = -centre ** 2 / (2 * RC), -(length - centre) ** 2 / (2 * RC)
        return [f0, f0 + length * centre / (2 * RC), f1]
    pu, pv = poles_1d(LX, 20.0), poles_1d(LY, 15.0)
    poles = [[[LX * i / 2, LY * j / 2, 10.0 + pu[i] + pv[j]] for j in range(3)] for i in range(3)]
    return parse_surface({"type": "bezier", "poles": poles})


@pytest.fixture(scope="module")
def mesh_file(tmp_path_factory):
    return write_grid_stl(tmp_path_factory.mktemp("mesh") / "paraboloid.stl")


def _mesh_height(surface, x, y):
    """The mesh's own linear interpolant (matplotlib's triangle finder, independent of ours)."""
    import matplotlib.tri as mtri

    v = surface.mesh.vertices
    tri = mtri.Triangulation(v[:, 0], v[:, 1], surface.mesh.faces)
    return np.ma.filled(mtri.LinearTriInterpolator(tri, v[:, 2])(x, y), np.nan)


def test_fit_deviation_is_reported_and_bounds_the_fit(mesh_file):
    s = parse_surface({"type": "mesh", "file": str(mesh_file)})
    fit = s.facts()["fit"]
    dev = fit["max_deviation_mm"]
    assert 0 < dev <= fit["limit_mm"] == 0.005
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0, LX, 20000), rng.uniform(0, LY, 20000)
    mesh = _mesh_height(s, x, y)
    # the mesh is the paraboloid's interpolant: within the closed-form sag (float32 file)
    assert np.nanmax(np.abs(mesh - fz(x, y))) <= SAG + 1e-5
    # the reported deviation is the fit's largest distance from the mesh (no point found farther)
    fit_z = s.height(x, y)
    assert np.nanmax(np.abs(fit_z - mesh)) <= dev * 1.05
    assert np.nanmax(np.abs(fit_z - mesh)) >= 0.5 * dev
    # and so the fit is within deviation + sag of the analytic surface
    assert np.abs(fit_z - fz(x, y)).max() <= dev + SAG + 1e-5


def test_fit_curvatures_match_the_paraboloid(mesh_file):
    s = parse_surface({"type": "mesh", "file": str(mesh_file)})
    exact = exact_surface()
    rng = np.random.default_rng(1)
    u, v = rng.uniform(0.1, 0.9, (2, 500))  # away from the edges the fit extrapolates to
    k_mesh = np.stack(s.principal_curvatures(u, v))
    k_exact = np.stack(exact.principal_curvatures(u, v))
    assert np.abs(k_mesh - k_exact).max() < 0.03 / RC
    assert np.abs(s.normals(u, v) - exact.normals(u, v)).max() < 5e-4  # 0.03 deg (measured 2.6e-4)


def test_units_scale_the_file_to_mm(mesh_file):
    mm = parse_surface({"type": "mesh", "file": str(mesh_file)})
    with pytest.raises(ValueError, match=r"the fit is 0.02\d* mm off the mesh at .* above max_deviation"):
        parse_surface({"type": "mesh", "file": str(mesh_file), "units": "cm"})  # 10x the sag
    cm = parse_surface({"type": "mesh", "file": str(mesh_file), "units": "cm", "max_deviation": 0.05})
    assert cm.facts()["fit"]["max_deviation_mm"] == pytest.approx(
        10 * mm.facts()["fit"]["max_deviation_mm"], rel=0.01)
    assert cm.bounds == pytest.approx(tuple(10 * b for b in mm.bounds))
    assert cm.points([0.5], [0.5])[0] == pytest.approx(10 * mm.points([0.5], [0.5])[0], rel=1e-6)
    with pytest.raises(ValueError, match=r"^surface.units: Input should be 'mm', 'cm'"):
        parse_surface({"type": "mesh", "file": str(mesh_file), "units": "furlong"})


def test_simulation_measures_the_mesh_and_agrees_with_the_analytic_plan(mesh_file):
    mesh = parse_surface({"type": "mesh", "file": str(mesh_file)})
    dev = mesh.facts()["fit"]["max_deviation_mm"]
    exact = exact_surface()
    h = 0.2
    g_mesh, g_exact = design_grid(mesh, h), design_grid(exact, h)
    # the mesh's design grid is the mesh: its interpolant at the cell centres, facet normals
    X, Y = np.meshgrid(g_mesh.xs, g_mesh.ys)
    on = g_mesh.inside
    np.testing.assert_allclose(g_mesh.z[on], _mesh_height(mesh, X[on], Y[on]), atol=1e-9)
    assert np.abs(g_mesh.z[on] - mesh.height(X[on], Y[on])).max() > 0.3 * dev  # not the fit
    assert on.sum() == g_exact.inside.sum()
    metrics = {}
    for name, surface, grid in (("mesh", mesh, g_mesh), ("exact", exact, g_exact)):
        pr = ToolpathProblem(surface=surface, tools=[{"id": 1, "type": "ball", "diameter": 10}],
                             machine="3axis", weights={"cc_count": 1.0},
                             normalization={"cc_count": [0, 1]},
                             ranges={"stepover": [10, 40], "step": [0.5, 4]})
        path, _ = pr.cl_path({"tool": 1, "stepover": 30, "step": 2.0})
        metrics[name] = simulate(path, grid).metrics
    m, e = metrics["mesh"], metrics["exact"]
    assert e["scallop_max_mm"] > 0.2  # a real cusp (10 mm ball, 3 mm step-over)
    for k in ("scallop_max_mm", "scallop_mean_mm", "gouge_max_mm"):
        assert abs(m[k] - e[k]) <= dev, (k, m[k], e[k], dev)


def test_a_mesh_with_a_hole_is_fitted_exactly_and_its_footprint_has_the_hole(tmp_path):
    xs, ys = np.linspace(0, 40, 41), np.linspace(0, 30, 31)
    X, Y = np.meshgrid(xs, ys)
    tri = PART["grid_triangles"](xs, ys, 5 + 0.01 * X + 0.02 * Y)  # a plane
    c = tri.mean(axis=1)
    hole = (np.abs(c[:, 0] - 20) < 5) & (np.abs(c[:, 1] - 15) < 4)  # 10 x 8 mm removed
    (tmp_path / "hole.stl").write_bytes(PART["stl_bytes"](tri[~hole]))
    s = parse_surface({"type": "mesh", "file": str(tmp_path / "hole.stl")})
    assert s.facts()["fit"]["max_deviation_mm"] < 1e-5  # a plane: the fit ignores the hole
    fp = s.footprint
    assert not fp.whole and len(fp.loops) == 2
    assert fp.area() == pytest.approx(1 - 80 / 1200, abs=1e-12)
    assert not fp.contains([0.5], [0.5])[0] and fp.contains([0.1], [0.1])[0]
    g = design_grid(s, 0.5)
    X, Y = np.meshgrid(g.xs, g.ys)
    assert not (g.inside & (np.abs(X - 20) < 5) & (np.abs(Y - 15) < 4)).any()  # no cell in the hole
    assert g.cell_area().sum() == pytest.approx(1120 * np.sqrt(1 + 0.01 ** 2 + 0.02 ** 2), rel=1e-9)


def test_obj_and_ply_give_the_stl_surface(mesh_file, tmp_path):
    import trimesh

    stl = parse_surface({"type": "mesh", "file": str(mesh_file)})
    m = trimesh.Trimesh(stl.mesh.vertices, stl.mesh.faces, process=False)
    u, v = np.random.default_rng(2).random((2, 200))
    for suffix in (".obj", ".ply"):
        path = tmp_path / f"paraboloid{suffix}"
        m.export(path)
        other = parse_surface({"type": "mesh", "file": str(path)})
        assert other.facts()["triangles"] == stl.facts()["triangles"]
        assert np.abs(other.points(u, v) - stl.points(u, v)).max() < 1e-5  # OBJ writes 8 digits


def test_a_closed_solid_is_machined_on_its_top_skin(tmp_path):
    """A block 40 x 30 mm from z = 0 up to the paraboloid (a closed solid, as CAD exports a
    part): facing: up keeps the top, which is the open paraboloid mesh exactly."""
    import trimesh

    top = parse_surface({"type": "mesh", "file": str(write_grid_stl(tmp_path / "top.stl"))})
    v, f = top.mesh.vertices, top.mesh.faces
    m = trimesh.Trimesh(v, f, process=False)
    edges = m.edges[trimesh.grouping.group_rows(m.edges_sorted, require_count=1)]  # boundary, wound
    n = len(v)
    floor = v.copy()
    floor[:, 2] = 0.0
    walls = np.concatenate([np.column_stack([edges[:, 1], edges[:, 0], edges[:, 0] + n]),
                            np.column_stack([edges[:, 1], edges[:, 0] + n, edges[:, 1] + n])])
    solid = trimesh.Trimesh(np.concatenate([v, floor]), np.concatenate([f, f[:, ::-1] + n, walls]),
                            process=False)
    assert solid.is_watertight and solid.is_winding_consistent and solid.volume > 0
    for flip in (False, True):  # wound inward: turned outward by its signed volume
        faces = solid.faces[:, ::-1] if flip else solid.faces
        trimesh.Trimesh(solid.vertices, faces, process=False).export(tmp_path / "solid.stl")
        with pytest.raises(ValueError, match=r"solid.stl: not a height field over XY: vertical wall at"):
            parse_surface({"type": "mesh", "file": str(tmp_path / "solid.stl")})
        s = parse_surface({"type": "mesh", "file": str(tmp_path / "solid.stl"), "facing": "up"})
        assert s.facts()["triangles"] == len(f) and s.bounds == pytest.approx(top.bounds)
        u, w = np.random.default_rng(3).random((2, 100))
        assert np.abs(s.points(u, w) - top.points(u, w)).max() < 1e-9
    with pytest.raises(ValueError, match=r"top.stl: facing: up takes a closed solid: \d+ edges belong to one"):
        parse_surface({"type": "mesh", "file": str(tmp_path / "top.stl"), "facing": "up"})
