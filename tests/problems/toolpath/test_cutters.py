"""Cutters: registry, exact profile geometry, CC -> tip, R_eff, APT, and the drop-cutter
against closed forms (plane, sphere, cylinder, patch edge) and against dense independent
sampling of Fountas' and Choi's surfaces (and opencamlib where it is installed)."""

from functools import lru_cache

import numpy as np
import pytest
from scipy.spatial import cKDTree
from toolpath_analytic import Cylinder, Plane, Sphere

from evoplan.problems.toolpath.cutters import (
    CUTTERS, BallEndCutter, FlatEndCutter, ToroidalCutter, cutter_from_tool, make_cutter)
from evoplan.problems.toolpath.cutters.surface_grid import surface_grid
from evoplan.problems.toolpath.cutters.effective_radius import (
    effective_radius_3axis, effective_radius_lead_tilt)
from evoplan.problems.toolpath.geometry.spec import parse_surface
from evoplan.problems.toolpath.spec import parse_tools

SHAPES = [(8.0, 0.0), (8.0, 1.0), (8.0, 4.0)]


def test_registry_infers_and_checks_the_shape():
    assert type(make_cutter(12, 0)) is FlatEndCutter
    assert type(make_cutter(12, 6)) is BallEndCutter
    assert type(make_cutter(12, 2)) is ToroidalCutter
    assert CUTTERS["torus"] is CUTTERS["toroidal"] is ToroidalCutter
    assert type(make_cutter(12, kind="ball")) is BallEndCutter  # r implied by the name
    assert make_cutter(12, kind="flat").corner_radius == 0.0
    with pytest.raises(ValueError, match=r"cutter.type: 'ball' does not match D 12, r 2"):
        make_cutter(12, 2, kind="ball")
    with pytest.raises(ValueError, match=r"cutter.corner_radius: must be in \[0, D/2 = 6\]"):
        make_cutter(12, 7)
    with pytest.raises(ValueError, match="cutter.diameter: must be a finite number > 0"):
        make_cutter(0, 0)
    with pytest.raises(ValueError, match="cutter.corner_radius: missing"):
        make_cutter(12, kind="torus")
    with pytest.raises(ValueError, match="cutter.type: expected one of"):
        make_cutter(12, 2, kind="cone")
    tools = parse_tools()
    kinds = [cutter_from_tool(t).kind for t in tools.tools]
    assert kinds == [t.type for t in tools.tools]


@pytest.mark.parametrize("d, r", SHAPES)
def test_height_and_width_are_the_exact_circle_profile(d, r):
    c = make_cutter(d, r)
    big, r0 = d / 2, d / 2 - r
    rho = np.linspace(0.0, big, 401)
    expect = np.where(rho <= r0, 0.0, r - np.sqrt(np.maximum(r * r - (rho - r0) ** 2, 0.0)))
    assert np.allclose(c.height(rho), expect, atol=1e-12)
    assert np.isinf(c.height([big * 1.001, 2 * big])).all()
    h = np.linspace(0.0, r, 50, endpoint=False)[1:]
    if r > 0:  # the width inverts the height on the corner arc
        assert np.allclose(c.height(c.width(h)), h, atol=1e-9)
    assert np.allclose(c.width([r, r + 1.0, 50.0]), big)
    assert np.isnan(c.width(-0.1))
    # the derivatives in s = rho^2 / 2 agree with finite differences
    s = 0.5 * np.linspace(0.1, 0.98 * big, 60) ** 2
    g, g1, g2 = c.height_jet(s)
    eps = 1e-6
    assert np.allclose(g1, (c.height_jet(s + eps)[0] - c.height_jet(s - eps)[0]) / (2 * eps),
                       rtol=1e-4, atol=1e-6)
    assert np.allclose(g2, (c.height_jet(s + eps)[1] - c.height_jet(s - eps)[1]) / (2 * eps),
                       rtol=1e-3, atol=1e-4)


def _end_samples(c, axis, m=300):
    """Dense points of the cutting end (rim circle swept by the corner ball), tip at 0."""
    a = axis / np.linalg.norm(axis)
    e1 = np.cross(a, [0.3, 0.5, 0.8])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    th = np.linspace(0, 2 * np.pi, m)[:, None, None]
    ph = np.linspace(-np.pi / 2, np.pi / 2, m // 2)[None, :, None]
    rim = np.cos(th) * e1 + np.sin(th) * e2
    r = c.corner_radius
    pts = r * a + c.rim_radius * rim + r * (np.cos(ph) * rim + np.sin(ph) * a)
    return pts.reshape(-1, 3)


@pytest.mark.parametrize("d, r", SHAPES)
def test_support_point_is_the_furthest_point_of_the_cutting_end(d, r):
    c = make_cutter(d, r)
    rng = np.random.default_rng(3)
    axis = np.array([0.2, -0.3, 1.0])
    dirs = rng.normal(size=(40, 3))
    dirs[:, 2] = -np.abs(dirs[:, 2])  # downward: the shank is not involved
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    sup = c.support_point(axis, dirs)
    pts = _end_samples(c, axis)
    best = (pts @ dirs.T).max(axis=0)
    reach = np.einsum("ij,ij->i", sup, dirs)
    assert np.all(reach >= best - 1e-12)  # nothing sampled lies further
    assert np.all(reach - best < 5e-4 * d)  # and the sampled solid gets there


@pytest.mark.parametrize("d, r", SHAPES)
def test_cc_to_tip_is_the_torus_offset_and_tangent(d, r):
    c = make_cutter(d, r)
    rng = np.random.default_rng(4)
    n = rng.normal(size=(30, 3))
    n[:, 2] = np.abs(n[:, 2]) + 0.3
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    cc = rng.uniform(-10, 10, (30, 3))
    for axis in (np.array([0.0, 0.0, 1.0]), np.array([0.3, 0.1, 0.95])):
        a = axis / np.linalg.norm(axis)
        tip = c.cc_to_tip(cc, n, axis)
        e = -n - np.sum(-n * a, axis=1, keepdims=True) * a
        e /= np.linalg.norm(e, axis=1, keepdims=True)
        assert np.allclose(tip, cc + r * n - (d / 2 - r) * e - r * a, atol=1e-12)
        # the placed cutter's lowest point along -n is cc: it touches the tangent plane there
        pts = _end_samples(c, a)
        depth = np.einsum("kmj,kj->km", tip[:, None, :] + pts[None] - cc[:, None, :], n)
        assert np.all(depth.min(axis=1) > -1e-12) and np.all(depth.min(axis=1) < 5e-4 * d)


def test_effective_radius_calls_the_paper_forms_and_the_ball_is_r_everywhere():
    lead, tilt = np.radians([3.0, 10.0]), np.radians([0.5, 2.0])
    for d, r in SHAPES:
        c = make_cutter(d, r)
        assert np.allclose(c.effective_radius_lead_tilt(lead, tilt),
                           effective_radius_lead_tilt(d / 2, r, lead, tilt))
        assert np.allclose(c.effective_radius(np.sin(lead), np.cos(lead) * np.cos(tilt)),
                           effective_radius_lead_tilt(d / 2, r, lead, tilt))
    slope, phi, alpha = np.radians([0.0, 20.0]), np.radians([10.0, 30.0]), np.radians([0.0, 45.0])
    torus = make_cutter(8, 1)
    assert np.allclose(torus.effective_radius_3axis(slope, phi, alpha),
                       effective_radius_3axis(4, 1, slope, alpha, phi))
    assert np.isinf(torus.effective_radius_3axis(0.0, 0.0, 0.0))  # the flat bottom cuts
    assert np.allclose(make_cutter(8, 4).effective_radius_3axis(slope, phi, alpha), 4.0)


def test_apt_cutter_statement():
    assert make_cutter(16, 3).apt_cutter() == "CUTTER/16.0000,3.0000"
    assert make_cutter(6.35, 0).apt_cutter() == "CUTTER/6.3500,0.0000"


@pytest.mark.parametrize("d, r", SHAPES)
def test_drop_on_a_tilted_plane_is_the_closed_form(d, r):
    plane = Plane(a=0.3, b=-0.2, c=5.0)
    xy = np.random.default_rng(5).uniform([10, 10], [90, 50], (200, 2))
    z = make_cutter(d, r).drop_cutter(plane, xy)
    slope = np.arctan(np.hypot(0.3, 0.2))
    # rim (R - r) tan S higher, plus the corner ball's r (1 / cos S - 1)
    expect = 0.3 * xy[:, 0] - 0.2 * xy[:, 1] + 5 + (d / 2 - r) * np.tan(slope) \
        + r * (1 / np.cos(slope) - 1)
    assert np.abs(z - expect).max() < 1e-9


@pytest.mark.parametrize("d, r", SHAPES)
def test_drop_on_a_sphere_cap_is_the_closed_form(d, r):
    rho = 30.0
    xy = np.random.default_rng(6).uniform(-10, 10, (200, 2))
    z = make_cutter(d, r).drop_cutter(Sphere(rho, half=20.0), xy)
    dist = np.linalg.norm(xy, axis=1)
    off = np.abs(dist - (d / 2 - r))  # the corner circle's nearest point to the axis
    # the corner ball's centre lies rho + r from the sphere's centre (ball: R_s + R);
    # where the flat bottom covers the apex, it rests on it
    expect = np.where(dist <= d / 2 - r, rho, np.sqrt((rho + r) ** 2 - off ** 2) - r)
    assert np.abs(z - expect).max() < 1e-9


@pytest.mark.parametrize("d, r", SHAPES)
def test_drop_on_cylinders_is_the_closed_form(d, r):
    rho = 35.0  # > the half-width 30 of the test cylinders: no NaN points
    xy = np.column_stack([np.random.default_rng(7).uniform(-12, 12, 150), np.full(150, 30.0)])
    z = make_cutter(d, r).drop_cutter(Cylinder(rho, axis="y", sign=1.0), xy)
    x = np.abs(xy[:, 0])
    r0 = d / 2 - r
    expect = np.where(x <= r0, rho, np.sqrt((rho + r) ** 2 - (x - r0) ** 2) - r)
    assert np.abs(z - expect).max() < 1e-9
    if r == d / 2:  # a ball in a trough: its centre rho - R from the axis
        z = make_cutter(d, r).drop_cutter(Cylinder(rho, axis="y", sign=-1.0), xy)
        assert np.abs(z - (-np.sqrt((rho - r) ** 2 - x ** 2) - r)).max() < 1e-9


@pytest.mark.parametrize("d, r", SHAPES)
def test_drop_over_the_patch_edge_rests_on_the_edge(d, r):
    # a plane rising to x = 100, cutter axis 1 mm inside: the edge line is the highest
    # material the cutter can meet; its lowest profile point over it is height(1)
    plane = Plane(a=0.3, b=0.0, c=0.0)
    xy = np.array([[99.0, 20.0], [99.0, 30.5]])
    c = make_cutter(d, r)
    assert np.allclose(c.drop_cutter(plane, xy), 30.0 - c.height(1.0), atol=1e-9)


@lru_cache(maxsize=None)
def _part(name, n=400_000):
    """The surface, random samples of it with their KD-tree, and the clearance the sample
    spacing allows (twice the spacing times the steepest slope)."""
    surface = parse_surface(name)
    uv = np.random.default_rng(0).uniform(0, 1, (n, 2))
    pts = surface.points(uv[:, 0], uv[:, 1])
    nz = surface.normals(uv[:, 0], uv[:, 1])[:, 2]
    ext = np.ptp(pts[:, :2], axis=0)
    allowed = 2 * np.sqrt(ext[0] * ext[1] / n) * (np.sqrt(1 - nz * nz) / nz).max()
    return surface, pts, cKDTree(pts[:, :2]), allowed


def _dense_check(name, cutter, xy):
    """(max penetration, max contact gap, max sampled clearance, allowed clearance)."""
    surface, pts, tree, allowed = _part(name)
    tip, contact = cutter.drop_cutter(surface, xy, return_contact=True)
    pen, clear = [], []
    for i, idx in enumerate(tree.query_ball_point(xy, cutter.radius)):
        d = pts[idx, :2] - xy[i]
        f = pts[idx, 2] - cutter.height(np.hypot(d[:, 0], d[:, 1]))
        pen.append(f.max() - tip[i])
        clear.append(tip[i] - f.max())
    cp = surface.points(contact[:, 0], contact[:, 1])
    rho = np.hypot(*(cp[:, :2] - xy).T)
    gap = cp[:, 2] - cutter.height(np.minimum(rho, cutter.radius)) - tip
    assert np.all(rho <= cutter.radius * (1 + 1e-7))
    return max(pen), np.abs(gap).max(), max(clear), allowed


@pytest.mark.parametrize("name", ["fountas", "choi"])
@pytest.mark.parametrize("d, r", [(6.35, 0.0), (6.35, 1.0), (6.35, 3.175), (16.0, 3.0)])
def test_drop_never_gouges_and_touches_on_free_form_parts(name, d, r):
    pts = _part(name)[1]
    lo, hi = pts[:, :2].min(axis=0), pts[:, :2].max(axis=0)
    xy = np.random.default_rng(2).uniform(lo - 2, hi + 2, (100, 2))  # edges included
    pen, gap, clear, allowed = _dense_check(name, make_cutter(d, r), xy)
    assert pen < 1e-9  # no sampled surface point above the cutter's profile
    assert gap < 1e-9  # the returned contact point touches the profile
    assert clear < allowed  # and the samples come as close to it as their spacing allows


def test_drop_agrees_with_opencamlib_on_a_triangulated_choi_surface():
    ocl = pytest.importorskip("opencamlib")
    surface = parse_surface("choi")
    n = 81
    t = np.linspace(0, 1, n)
    uu, vv = np.meshgrid(t, t, indexing="ij")
    p = surface.points(uu.ravel(), vv.ravel()).reshape(n, n, 3)
    # vertical error of the triangulation: the surface at mid-edges vs the chords
    mid = surface.points(0.5 * (uu[1:, 1:] + uu[:-1, :-1]).ravel(),
                         0.5 * (vv[1:, 1:] + vv[:-1, :-1]).ravel())[:, 2]
    sag = np.abs(mid - 0.5 * (p[1:, 1:, 2] + p[:-1, :-1, 2]).ravel()).max()
    stl = ocl.STLSurf()

    def pt(q):
        return ocl.Point(float(q[0]), float(q[1]), float(q[2]))

    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = p[i, j], p[i + 1, j], p[i + 1, j + 1], p[i, j + 1]
            stl.addTriangle(ocl.Triangle(pt(a), pt(b), pt(c)))
            stl.addTriangle(ocl.Triangle(pt(a), pt(c), pt(d)))
    xy = np.random.default_rng(8).uniform([5, 5], [45, 70], (30, 2))
    for d, r, tool in [(6.35, 0.0, ocl.CylCutter(6.35, 20.0)),
                       (6.35, 1.0, ocl.BullCutter(6.35, 1.0, 20.0)),
                       (6.35, 3.175, ocl.BallCutter(6.35, 20.0))]:
        bdc = ocl.BatchDropCutter()
        bdc.setSTL(stl)
        bdc.setCutter(tool)
        for x, y in xy:
            bdc.appendPoint(ocl.CLPoint(float(x), float(y), -100.0))
        bdc.run()
        z_ocl = np.array([q.z for q in bdc.getCLPoints()])
        z = make_cutter(d, r).drop_cutter(surface, xy)
        assert np.abs(z - z_ocl).max() <= 2 * sag + 1e-6, (d, r, sag)


@pytest.mark.parametrize("d, r", SHAPES)
def test_drop_on_a_disk_that_grazes_the_patch_edge(d, r):
    # the disk overlaps the footprint x <= 100 by 2 um (a chord of +-0.13 mm on the edge)
    # midway between the seed grid's edge points (spacing R / 10 = 0.4 mm: y = 20.0, 20.4)
    plane = Plane(a=0.3, b=0.0, c=0.0)
    c = make_cutter(d, r)
    depth = 0.002
    xy = np.array([[100.0 + d / 2 - depth, 20.2], [100.0 + d / 2 + 0.1, 20.0]])
    grid = surface_grid(plane, 0.4)
    assert np.min(np.hypot(*(grid.xy - xy[0]).T)) > c.radius  # no seed in the disk
    z = c.drop_cutter(plane, xy)
    assert np.isclose(z[0], 30.0 - c.height(d / 2 - depth), atol=1e-9)
    assert z[1] == -np.inf  # off the part: nothing to touch
