"""NURBS surfaces: exact conics (cylinder, sphere), weights 1 = B-spline, one-line bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.geometry.bspline import BSplineSurface
from evoplan.problems.toolpath.geometry.nurbs import NURBSSurface
from evoplan.problems.toolpath.geometry.spec import parse_surface

R, L = 40.0, 60.0
S = float(np.sqrt(0.5))


def cylinder_spec(radius=R, length=L, half_angle=45.0) -> dict:
    """The top of a cylinder of axis X (the arc from 90 - a to 90 + a deg; a quarter by
    default): a rational quadratic arc in u (its middle weight cos a) swept along X in v."""
    c, s = float(np.cos(np.radians(half_angle))), float(np.sin(np.radians(half_angle)))
    arc = [(radius * s, radius * c), (0.0, radius / c), (-radius * s, radius * c)]
    poles = [[[x, y, z] for x in (0.0, length)] for y, z in arc]
    weights = [[w, w] for w in (1.0, c, 1.0)]
    return {"type": "nurbs", "degree": [2, 1], "poles": poles, "weights": weights}


def sphere_octant(radius=R) -> NURBSSurface:
    """x, y, z >= 0 of a sphere: the quarter meridian (u) revolved a quarter turn (v)."""
    prof = [(radius, 0.0, 1.0), (radius, radius, S), (0.0, radius, 1.0)]  # (r, z, w)
    circ = [(1.0, 0.0, 1.0), (1.0, 1.0, S), (0.0, 1.0, 1.0)]  # (cx, cy, w)
    poles = [[[r * cx, r * cy, z] for cx, cy, _ in circ] for r, z, _ in prof]
    weights = [[wp * wc for *_, wc in circ] for *_, wp in prof]
    return NURBSSurface(poles, weights, (2, 2))


def grid(n=23, hi=1.0):
    u, v = np.meshgrid(np.linspace(0, hi, n), np.linspace(0, 1, n))
    return u.ravel(), v.ravel()


def test_cylinder_is_exact_points_normals_curvatures():
    surf = parse_surface(cylinder_spec())
    u, v = grid()
    p = surf.points(u, v)
    radial = p[:, 1:] / np.linalg.norm(p[:, 1:], axis=1, keepdims=True)
    assert np.abs(np.linalg.norm(p[:, 1:], axis=1) - R).max() < 1e-9
    assert np.abs(p[:, 0] - L * v).max() < 1e-9
    n = surf.normals(u, v)
    assert np.abs(n[:, 0]).max() < 1e-9 and np.abs(n[:, 1:] - radial).max() < 1e-9
    k_min, k_max = surf.principal_curvatures(u, v)
    assert np.abs(k_min + 1 / R).max() < 1e-9  # convex seen from the tool above
    assert np.abs(k_max).max() < 1e-9  # straight along the axis


def test_sphere_octant_is_exact_points_normals_curvatures():
    surf = sphere_octant()
    u, v = grid(hi=0.95)  # the meridians meet at the pole (u = 1): no normal there
    p = surf.points(u, v)
    r = np.linalg.norm(p, axis=1)
    assert np.abs(r - R).max() < 1e-9 and p.min() > -1e-9
    assert np.abs(surf.normals(u, v) - p / r[:, None]).max() < 1e-9
    k_min, k_max = surf.principal_curvatures(u, v)
    assert np.abs(k_min + 1 / R).max() < 1e-9 and np.abs(k_max + 1 / R).max() < 1e-9


def test_second_derivatives_match_finite_differences_of_the_first():
    surf = sphere_octant()
    u, v = np.array([0.3, 0.6]), np.array([0.2, 0.7])
    h = 1e-6
    j = surf.jet(u, v, 2)
    ju1, ju0 = surf.jet(u + h, v, 1), surf.jet(u - h, v, 1)
    jv1, jv0 = surf.jet(u, v + h, 1), surf.jet(u, v - h, 1)
    assert np.allclose(j.suu, (ju1.su - ju0.su) / (2 * h), atol=1e-5)
    assert np.allclose(j.suv, (jv1.su - jv0.su) / (2 * h), atol=1e-5)
    assert np.allclose(j.svv, (jv1.sv - jv0.sv) / (2 * h), atol=1e-5)
    assert np.allclose(j.su, (surf.points(u + h, v) - surf.points(u - h, v)) / (2 * h), atol=1e-5)


def test_weights_one_equal_the_bspline_type():
    rng = np.random.default_rng(7)
    x, y = np.meshgrid(np.linspace(0, 50, 6), np.linspace(0, 40, 5), indexing="ij")
    poles = np.stack([x, y, rng.uniform(0, 5, x.shape)], axis=2)
    knots_u = [0, 0, 0, 0, 0.3, 0.5, 1, 1, 1, 1]
    b = BSplineSurface(poles, (3, 3), knots_u)
    n = NURBSSurface(poles, np.ones((6, 5)), (3, 3), knots_u)
    u, v = grid(17)
    jb, jn = b.jet(u, v, 2), n.jet(u, v, 2)
    for fb, fn in zip(jb, jn):
        assert np.abs(fb - fn).max() < 1e-12 * max(1.0, np.abs(fb).max())
    assert b.normal_sign == n.normal_sign


def test_weights_from_files(tmp_path):
    spec = cylinder_spec()
    (tmp_path / "w.csv").write_text("i,j,w\n" + "".join(
        f"{i},{j},{w}\n" for i, row in enumerate(spec["weights"]) for j, w in enumerate(row)))
    (tmp_path / "w.yaml").write_text(f"weights: {spec['weights']}\n")
    u, v = grid(9)
    ref = parse_surface(spec).points(u, v)
    for name in ("w.csv", "w.yaml"):
        surf = parse_surface({**spec, "weights": name}, base_dir=tmp_path)
        assert np.abs(surf.points(u, v) - ref).max() < 1e-12


# through the CLI (exit 2, one line, no folder): the nurbs_* cases of test_toolpath_cli.py
BAD_WEIGHTS = {
    "zero": ([[1, 1], [0, 0.7], [1, 1]], "surface.weights: weights must be > 0, got 0 at [1][0]"),
    "negative": ([[1, 1], [0.7, -2], [1, 1]], "surface.weights: weights must be > 0"),
    "shape": ([[1, 1], [1, 1]], "surface.weights: expected shape (3, 2) (one weight per pole), "
              "got (2, 2)"),
    "nan": ([[1, 1], [".nan", 1], [1, 1]], "surface.weights: contains NaN or infinite values"),
    "inf": ([[1, 1], [".inf", 1], [1, 1]], "surface.weights: contains NaN or infinite values"),
    "missing": (None, "surface.weights: missing"),
}


def bad_spec(case) -> dict:
    weights, _ = BAD_WEIGHTS[case]
    spec = cylinder_spec()
    if weights is None:
        del spec["weights"]
    else:
        spec["weights"] = [[float(w.lstrip(".")) if isinstance(w, str) else w for w in row] for row in weights]
    return spec


@pytest.mark.parametrize("case", sorted(BAD_WEIGHTS))
def test_bad_weights_are_refused_in_one_line_naming_the_key(case):
    with pytest.raises(ValueError) as err:
        parse_surface(bad_spec(case))
    assert str(err.value).startswith(BAD_WEIGHTS[case][1]) and "\n" not in str(err.value)


def test_the_shipped_nurbs_run_machines_an_exact_cylinder():
    import yaml

    root = Path(__file__).resolve().parents[3]
    cfg = yaml.safe_load((root / "runs" / "nurbs_cylinder_vega.yaml").read_text())
    surf = parse_surface(cfg["problem"]["params"]["surface"])
    u, v = grid()
    ref = parse_surface(cylinder_spec(40.0, 60.0))
    assert np.abs(surf.points(u, v) - ref.points(u, v)).max() < 1e-9
    assert surf.normal_sign == ref.normal_sign


def test_a_ball_swept_over_the_nurbs_cylinder_leaves_the_circle_intersection_cusp():
    """The cut simulation on the NURBS cylinder's design grid (0.05 mm cells): ball passes
    along the axis, 8 deg apart, leave the cusp of two intersecting ball circles."""
    from evoplan.problems.toolpath.clpath import CLPath
    from evoplan.problems.toolpath.simulation import design_grid, sweep_path

    rho, r, dphi, h = 30.0, 4.0, np.radians(8.0), 0.05
    surf = parse_surface(cylinder_spec(rho, 20.0, half_angle=22.0))
    g = design_grid(surf, h)
    i = int(np.argmin(np.abs(g.y0 + h * np.arange(g.z.shape[0]))))  # the cell row nearest y = 0
    y_mid = g.y0 + i * h
    phis = np.arcsin(y_mid / rho) + dphi * (np.arange(-2, 3) + 0.5)
    d = rho + r  # ball centres on the offset cylinder, tips r below them (vertical axis)
    xs = np.linspace(-6.0, 26.0, 17)
    tips = np.array([(x, d * np.sin(p), d * np.cos(p) - r) for p in phis for x in xs])
    sec = np.repeat(np.arange(len(phis)), len(xs))
    axes = np.tile((0.0, 0.0, 1.0), (len(tips), 1))
    res = sweep_path(CLPath(tips, axes, make_cutter(2 * r, r), section=sec), g).values
    want = d * np.cos(dphi / 2) - np.sqrt(r * r - (d * np.sin(dphi / 2)) ** 2) - rho
    got = res[i, 60:340]
    assert got.max() == pytest.approx(want, rel=2e-3, abs=2e-5)
