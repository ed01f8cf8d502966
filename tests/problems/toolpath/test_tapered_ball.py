"""The tapered ball-end mill against closed forms: its profile (the cone tangent to the ball,
built here from the top rim and the ball alone), the effective radius (r on the ball, inf on
the developable cone, as the swept profile shows), the drop-cutter on planes and on a
sphere (ball, cone and rim contacts), the cut simulation (the ray entry, its derivative, a
cusp on an inclined plane, flank milling with the cone), APT CUTTER/ with its 7 parameters,
and a tool entry through the whole problem."""

import numpy as np
import pytest
from toolpath_analytic import Plane, Sphere

from evoplan.problems.toolpath.clpath import CLPath
from evoplan.problems.toolpath.cutters import (
    TaperedBallCutter, cutter_from_apt, cutter_from_dict, make_cutter)
from evoplan.problems.toolpath.export.apt_read import read_apt
from evoplan.problems.toolpath.export.apt_write import apt_program
from evoplan.problems.toolpath.simulation import analytic_grid, sweep_path
from evoplan.problems.toolpath.simulation.convex import _at
from evoplan.problems.toolpath.simulation.kernel import MISS, _entry, ray_entry
from evoplan.problems.toolpath.spec import parse_tools

D, R_BALL, BETA = 8.0, 1.0, 10.0


def _cutter(d=D, r=R_BALL, beta=BETA):
    return make_cutter(d, r, taper_angle=beta)


def test_registry_builds_and_checks_a_tapered_ball():
    c = make_cutter(8, 1, "tapered_ball", taper_angle=10)
    assert type(c) is TaperedBallCutter and c == _cutter() and c != make_cutter(8, 1)
    assert type(make_cutter(8, 1, taper_angle=10)) is TaperedBallCutter  # inferred
    assert cutter_from_dict(c.to_dict()) == c
    with pytest.raises(ValueError, match=r"^cutter.taper_angle: missing"):
        make_cutter(8, 1, "tapered_ball")
    with pytest.raises(ValueError, match=r"^cutter.taper_angle: must be in \(0, 90\) degrees, got 95"):
        make_cutter(8, 1, taper_angle=95)
    with pytest.raises(ValueError, match=r"^cutter.corner_radius: a tapered ball needs the ball's"):
        make_cutter(8, 0, taper_angle=10)
    with pytest.raises(ValueError, match=r"^cutter.taper_angle: a toroidal cutter has no taper_angle"):
        make_cutter(8, 1, "toroidal", taper_angle=10)
    db = parse_tools([{"type": "tapered_ball", "diameter": 8, "corner_radius": 1, "taper_angle": 10}])
    assert db.cutter(0) == c and "taper 10" in db.tools[0].label()
    with pytest.raises(ValueError, match=r"^tools\[0\].taper_angle: expected a number"):
        parse_tools([{"diameter": 8, "corner_radius": 1, "taper_angle": "steep"}])


@pytest.mark.parametrize("beta", [3.0, 10.0, 40.0])
def test_profile_is_the_hull_of_the_ball_and_the_top_rim(beta):
    # built without the module's formulas: the tangent from the top rim corner (R, H) to the
    # ball's circle (centre (0, r)) is the cone's side; it must make the angle beta with the
    # axis, and below it the profile is the ball
    c = _cutter(beta=beta)
    big, r, top = D / 2, R_BALL, c.cutting_height
    px, pz = big, top - r  # the corner relative to the ball's centre
    dist = np.hypot(px, pz)
    # tangent point T on the circle seen from P, on the outer (lower) side
    phi = np.arctan2(pz, px) - np.arccos(r / dist)
    tx, tz = r * np.cos(phi), r + r * np.sin(phi)
    side = np.degrees(np.arctan2(px - tx, pz - (tz - r)))  # the side's angle to the axis
    assert side == pytest.approx(beta, abs=1e-9)
    rho = np.linspace(0.0, big, 2001)
    want = np.where(rho <= tx, r - np.sqrt(np.maximum(r * r - rho * rho, 0.0)),
                    tz + (rho - tx) * (top - tz) / (big - tx))
    assert np.abs(c.height(rho) - want).max() < 1e-12
    assert np.isinf(c.height(big * 1.001))
    h = np.linspace(0.0, top, 300)
    assert np.allclose(c.height(c.width(h)), h, atol=1e-9)
    assert np.allclose(c.width([top, top + 5.0]), big) and np.isnan(c.width(-0.1))
    # the derivatives in s = rho^2 / 2 agree with finite differences
    s = 0.5 * np.linspace(0.05, 0.98 * big, 80) ** 2
    s = s[np.abs(np.sqrt(2 * s) - tx) > 1e-3]  # not across the tangency (g'' jumps there)
    g, g1, g2 = c.height_jet(s)
    e = 1e-6
    assert np.allclose(g1, (c.height_jet(s + e)[0] - c.height_jet(s - e)[0]) / (2 * e), rtol=1e-5)
    assert np.allclose(g2, (c.height_jet(s + e)[1] - c.height_jet(s - e)[1]) / (2 * e), rtol=1e-4,
                       atol=1e-6)
    # the support point along -n is the lowest point of the cutter seen from n
    rng = np.random.default_rng(2)
    n = rng.normal(size=(300, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    sup = c.support_point(np.array([0.0, 0.0, 1.0]), -n)
    th = np.linspace(0, 2 * np.pi, 721)
    ring = [np.stack([c.width(w) * np.cos(th), c.width(w) * np.sin(th), np.full_like(th, w)], 1)
            for w in np.linspace(0, top, 400)]
    pts = np.concatenate(ring)
    assert np.all(np.einsum("ij,ij->i", sup, -n) >= (pts @ -n.T).max(axis=0) - 1e-4)


def test_effective_radius_is_r_on_the_ball_and_infinite_on_the_cone():
    c = _cutter()
    sb = np.sin(np.radians(BETA))
    an = np.array([1.0, 0.5, sb + 1e-6, sb - 1e-3, 0.0])
    assert np.array_equal(c.effective_radius(0.3, an), [1.0, 1.0, 1.0, np.inf, np.inf])
    slopes = np.radians([0.0, 45.0, 79.0, 81.0])
    assert np.array_equal(c.effective_radius_3axis(slopes, 0.0, 0.3), [1.0, 1.0, 1.0, np.inf])
    assert c.effective_radius_lead_tilt(np.radians(80.5), 0.0) == np.inf
    # the swept profile shows it: on the ball the side width at a small height h is the
    # circle's sqrt(2 r h); on the cone the profile is straight (width linear in h)
    h = np.array([1e-4, 4e-4])
    x = c.swept_side_width(h, 0.0, np.radians(30.0))  # contact at 30 deg: the ball
    assert x == pytest.approx(np.sqrt(2 * R_BALL * h), rel=2e-3)
    steep = np.radians(85.0)  # a wall steeper than 90 - beta: the cone's generator touches
    x = c.swept_side_width(np.array([0.05, 0.1, 0.2]), 0.0, steep)
    assert np.allclose(np.diff(x), x[1] - x[0], rtol=1e-6)  # straight: curvature 0
    # and the 5-axis tables: at the contact the profile curves like the circle of radius r
    xs, zs, _ = c.swept_profile(np.radians([20.0]), np.radians([5.0]))
    sel = (xs[0] > 0.01) & (xs[0] < 0.05)
    assert np.allclose(zs[0][sel], R_BALL - np.sqrt(R_BALL ** 2 - xs[0][sel] ** 2), atol=2e-6)


@pytest.mark.parametrize("slope_deg", [20.0, 75.0, 85.0])
def test_drop_on_a_plane_is_the_closed_form(slope_deg):
    # ball contact: the centre r / cos S above the plane; past 90 - beta the top rim (R, H)
    # touches, R tan S - H above it (a plane touches a frustum's side only at S = 90 - beta)
    c = _cutter(beta=20.0)
    a = np.tan(np.radians(slope_deg))
    plane = Plane(x0=0.0, x1=40.0, y0=0.0, y1=40.0, a=a, b=0.0, c=0.0)
    xy = np.random.default_rng(5).uniform([8, 8], [32, 32], (60, 2))
    z = c.drop_cutter(plane, xy)
    S = np.radians(slope_deg)
    expect = a * xy[:, 0] + max(R_BALL * (1 / np.cos(S) - 1), D / 2 * np.tan(S) - c.cutting_height)
    assert np.abs(z - expect).max() < 1e-8


def test_drop_on_a_sphere_is_the_closed_form():
    # a cap of radius 30 about the origin, a tapered ball r 1, beta 50: the tip the lowest
    # over the pieces: the ball's centre rho + r from the sphere's centre, the cone's side
    # rho from it (where the foot of that distance lies on the frustum), the top rim
    c = _cutter(beta=50.0)
    rho, b, r, big, top = 30.0, np.radians(50.0), R_BALL, D / 2, c.cutting_height
    d = np.r_[np.linspace(0.0, 18.0, 10), np.linspace(20.5, 23.5, 10)]
    xy = np.stack([d, d], 1) / np.sqrt(2)
    z = c.drop_cutter(Sphere(rho, half=20.0), xy)
    t_ball = np.sqrt((rho + r) ** 2 - d ** 2) - r
    w_apex = r - r / np.sin(b)
    w_centre = w_apex + (d * np.cos(b) - rho) / np.sin(b)  # the sphere's centre, tool frame
    foot = w_centre + rho * np.sin(b)
    t_cone = np.where((foot >= c.tangency[1]) & (foot <= top), -w_centre, -np.inf)
    t_rim = np.sqrt(rho ** 2 - (d - big) ** 2) - top
    expect = np.maximum(np.maximum(t_ball, t_cone), t_rim)
    assert np.abs(z - expect).max() < 1e-8
    assert (t_cone > np.maximum(t_ball, t_rim) + 0.05).sum() >= 3  # the cone's contacts are tried


def test_ray_entry_is_the_profile_and_its_slope_the_derivative():
    c = _cutter()
    prm = c.kernel_params()
    for rho in (0.0, 0.5, c.tangency[0], 2.0, 3.9):
        got = ray_entry(rho, 0.0, -5.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, prm)
        assert got - 5.0 == pytest.approx(float(c.height(rho)), abs=1e-9)
    miss = ray_entry(D / 2 + 0.01, 0.0, -5.0, 0.0, 0.0, 1.0, 0, 0, 0, 0, 0, 1.0, prm)
    assert miss == pytest.approx(MISS + 0.01)
    # along a move with a turning axis, the entry's slope is its derivative (all faces)
    tip = np.array([[0.0, 0.0, 0.0], [5.0, 1.0, 0.4]])
    ax = np.array([[0.0, 0.0, 1.0], [0.3, 0.05, 1.0]])
    ax /= np.linalg.norm(ax, axis=1, keepdims=True)
    rng = np.random.default_rng(3)
    g = np.empty(6)
    faces = set()
    for _ in range(600):
        p = np.r_[rng.uniform(-4, 9, 2), rng.uniform(-1.0, 3.0)]
        dd = np.r_[rng.normal(0, 0.4, 2), 1.0]
        dd /= np.linalg.norm(dd)
        s, e = rng.uniform(0.05, 0.95), 1e-6
        f, slope, _ = _at(s, 0, 1, tip, ax, *p, *dd, prm, g)
        fp = _at(s + e, 0, 1, tip, ax, *p, *dd, prm, g)[0]
        fm = _at(s - e, 0, 1, tip, ax, *p, *dd, prm, g)[0]
        if max(f, fp, fm) > MISS / 2:
            continue
        if abs(fp - 2 * f + fm) > 1e-7:  # a kink (an edge of the faces) between the samples
            continue
        assert slope == pytest.approx((fp - fm) / (2 * e), abs=1e-5)
        a = ax[0] + s * (ax[1] - ax[0])
        faces.add(_entry(*p, *dd, *(tip[0] + s * (tip[1] - tip[0])), *(a / np.linalg.norm(a)),
                         prm, np.inf)[1])
    # the shank's side, the cone's side, the ball (kernel array: shank, cone, ball; the
    # shank's bottom disc lies inside the cone)
    assert {1, 4, 7} <= faces


def _row(grid, y):
    return int(round((y - grid.y0) / grid.h))


def test_simulated_cusp_on_an_inclined_plane_is_the_balls():
    # 3-axis passes along x on z = b y, the ball in contact (slope 30 < 90 - beta): the cusp
    # between passes s apart on the surface is the ball's r - sqrt(r^2 - s^2 / 4)
    c = _cutter(r=2.0)
    S = np.radians(30.0)
    b, h = np.tan(S), 0.05
    g = analytic_grid(lambda x, y: b * y, lambda x, y: (0 * x, 0 * x + b), (0, 30, 0, 20), h)
    dy = 1.5 * np.cos(S)  # s = 1.5 along the surface
    ys = 5.025 + dy * np.arange(5)
    tips, axes, sec = [], [], []
    for k, y in enumerate(ys):
        xs = np.linspace(-6.0, 36.0, 22)
        tips += [(x, y, b * y + 2.0 * (1 / np.cos(S) - 1)) for x in xs]
        axes += [(0, 0, 1)] * len(xs)
        sec += [k] * len(xs)
    res = sweep_path(CLPath(np.array(tips), np.array(axes), c, section=np.array(sec)), g).values
    # the contacts (and the cusp between two) lie r sin S uphill of the centres' XY
    y_cusp = ys[2] + dy / 2 + 2.0 * np.sin(S)
    i = _row(g, y_cusp)
    # the cell's centre lies within h / 2 of the cusp's line: the circle there
    off = abs(g.y0 + i * h - y_cusp) / np.cos(S)
    want = 2.0 - np.sqrt(4.0 - (1.5 / 2 - off) ** 2)
    assert res[i, 100:500].max() == pytest.approx(want, abs=2e-5)
    assert np.abs(res[_row(g, ys[2] + 2.0 * np.sin(S)), 100:500]).max() < 1e-4  # no gouge


def test_flank_of_the_cone_leaves_a_wall_flat():
    # a wall at 90 - beta to the horizontal: the cone's generator lies on it, so passes along
    # the wall closer than the generator's length leave nothing between them, and none gouges
    c = _cutter()
    S = np.radians(90.0 - BETA)
    b, h = np.tan(S), 0.05
    g = analytic_grid(lambda x, y: b * y, lambda x, y: (0 * x, 0 * x + b), (0, 30, 5, 8), h)
    n = np.array([0.0, -np.sin(S), np.cos(S)])  # the wall's unit normal
    length = (c.cutting_height - c.tangency[1]) / np.cos(np.radians(BETA))
    tips, axes, sec = [], [], []
    for k, y in enumerate(5.0 + 0.5 * np.arange(7)):  # contacts 0.5 / cos apart up the wall
        cc = np.array([0.0, y, b * y])
        tip = c.cc_to_tip(cc, n)  # touches the wall with the cone
        for x in np.linspace(-6.0, 36.0, 22):
            tips.append(tip + [x, 0.0, 0.0])
            axes.append((0, 0, 1))
            sec.append(k)
    assert 0.5 / np.sin(S) < length
    res = sweep_path(CLPath(np.array(tips), np.array(axes), c, section=np.array(sec)), g).values
    band = res[_row(g, 5.6):_row(g, 7.4), 100:500]
    assert np.isfinite(band).all() and np.abs(band).max() < 1e-5


def test_apt_cutter_has_its_seven_parameters_and_reads_back(tmp_path):
    c = _cutter()
    stmt = c.apt_cutter()
    values = [float(v) for v in stmt.split("/")[1].split(",")]
    r, b = R_BALL, np.radians(BETA)
    assert len(values) == 7
    assert values[:6] == pytest.approx([2 * r * (1 - np.sin(b)) / np.cos(b), r, 0.0, r, 0.0, BETA],
                                       abs=1e-4)
    assert values[0] + 2 * values[6] * np.tan(b) == pytest.approx(D, abs=1e-3)  # D at height h
    back = cutter_from_apt(values)
    assert type(back) is TaperedBallCutter and back.diameter == pytest.approx(D, abs=1e-3)
    assert back.taper_angle == BETA and back.corner_radius == r
    tip = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
    text = apt_program(tip, np.tile([0.0, 0.0, 1.0], (2, 1)), np.zeros(2, int), cutter=c,
                       feed_rate=800)
    (tmp_path / "t.apt").write_text(text)
    assert read_apt(tmp_path / "t.apt").cutter.taper_angle == BETA
    with pytest.raises(ValueError, match=r"no registered cutter shape has these parameters"):
        cutter_from_apt([8, 1, 0, 1, 10, 0, 20])  # a bottom angle: no such shape


def test_a_tapered_tool_runs_through_the_problem():
    from evoplan.problems.toolpath.problem import ToolpathProblem
    from evoplan.problems.toolpath.simulation import simulate

    tools = [{"id": 1, "type": "tapered_ball", "diameter": 10, "corner_radius": 3, "taper_angle": 5}]
    pr = ToolpathProblem(tools=tools, normalization_samples=2)
    genes = dict(tool=1, stepover=20.0, lead=5.0, tilt=1.0, step=6.0)
    crit = pr.evaluate_params(genes)
    assert all(np.isfinite(v) for v in crit.values())
    path, _ = pr.cl_path(genes)
    assert path.cutter == make_cutter(10, 3, taper_angle=5)
    sim = simulate(path, pr.surface, 1.0)
    assert np.isfinite(sim.metrics["scallop_max_mm"]) and sim.metrics["scallop_max_mm"] > 0
