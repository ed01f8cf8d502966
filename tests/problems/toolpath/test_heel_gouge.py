"""The pose gouge of a leaned cutter (criteria/heel.py): the flat end's heel against its closed
form on a trough concave along the feed, nothing on a plane, nothing for a ball in a bowl
flatter than it, and the analytic gouge against the cut simulation (trough, Fountas' part)."""

import numpy as np
import pytest
from toolpath_analytic import Cylinder, Plane, Sphere

from evoplan.problems.toolpath.criteria.heel import pose_gouge
from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.geometry.surface import unit_normal
from evoplan.problems.toolpath.problem import ToolpathProblem
from evoplan.problems.toolpath.simulation import simulate

CUTTERS = [make_cutter(16, 0), make_cutter(16, 3), make_cutter(16, 8)]
NORM = {"machining_error": [0, 0.5], "cc_count": [0, 1000]}


def _frame(surface, u, v, feed):
    """Jet, unit normal and unit travel tangent (the surface tangent over the XY direction
    ``feed``) at (u, v)."""
    jet = surface.jet(np.asarray(u, float), np.asarray(v, float), order=2)
    n = unit_normal(jet, surface.normal_sign)
    f = np.broadcast_to(np.asarray(feed, float), n.shape)
    t = f - (np.einsum("ij,ij->i", f, n) / n[:, 2])[:, None] * np.array([0.0, 0.0, 1.0])
    t = t / np.linalg.norm(t, axis=-1, keepdims=True)
    return jet, n, t


def _axis(n, t, lead, tilt):
    """The axis leaned by ``lead`` towards the travel and tilted by ``tilt`` across it (deg)."""
    lead, tilt = np.radians(lead), np.radians(tilt)
    b = np.cross(n, t)
    a = np.cos(lead) * n + np.sin(lead) * t
    return np.cos(tilt) * a + np.sin(tilt) * b


def _gouge(surface, cutter, u, v, feed, lead, tilt=0.0, tip=False):
    jet, n, t = _frame(surface, u, v, feed)
    a = _axis(n, t, lead, tilt)
    tips = cutter.cc_to_tip(jet.p, n, a) if tip else None
    return pose_gouge([cutter], 0, jet.p, n, t, a, jet, tip=tips)


def _heel_closed_form(radius, rho, lead):
    """max over x in [0, 2R cos lead] of x^2 / (2 rho) - x tan lead."""
    lead = np.radians(lead)
    x = np.linspace(0.0, 2 * radius * np.cos(lead), 20001)
    return np.max(x * x / (2 * rho) - x * np.tan(lead))


@pytest.mark.parametrize("lead", [1.0, 2.0])
@pytest.mark.parametrize("feed", [(1.0, 0.0, 0.0), (-1.0, 0.0, 0.0)])
def test_flat_end_heel_on_a_trough_is_the_closed_form(lead, feed):
    # trough z = -sqrt(rho^2 - x^2), axis along Y: fed along X the normal curvature along
    # the feed is 1 / rho everywhere, across it 0; a small curvature keeps the parabola exact
    rho = 200.0
    trough = Cylinder(rho, axis="y", sign=-1.0, half=40.0)
    u = np.array([0.5, 0.3, 0.7])  # x = 0, -16, 16 mm: bottom and both flanks
    got = _gouge(trough, CUTTERS[0], u, np.full(3, 0.5), feed, lead)
    want = _heel_closed_form(8.0, rho, lead)
    assert want > 0.02
    np.testing.assert_allclose(got, want, rtol=0.01)


def test_no_gouge_on_a_plane_whatever_the_lead_and_tilt():
    plane = Plane(-50, 50, -50, 50, a=0.2, b=-0.1)
    u, v = np.meshgrid(np.linspace(0.2, 0.8, 4), np.linspace(0.2, 0.8, 3))
    for cutter in CUTTERS:
        for lead, tilt in ((3.0, 0.0), (5.0, 2.0), (-2.0, -1.0)):
            for feed in ((1.0, 0.0, 0.0), (0.6, 0.8, 0.0)):
                got = _gouge(plane, cutter, u.ravel(), v.ravel(), feed, lead, tilt)
                assert np.all(got == 0.0), (cutter, lead, tilt)


def test_ball_in_a_bowl_flatter_than_it_does_not_gouge_but_a_flat_end_does():
    bowl = Sphere(20.0, sign=-1.0, half=12.0)  # curvature 1/20 < 1/R = 1/8
    u, v = np.meshgrid(np.linspace(0.25, 0.75, 3), np.linspace(0.25, 0.75, 3))
    u, v = u.ravel(), v.ravel()
    for lead, tilt in ((0.0, 0.0), (4.0, 2.0)):
        got = _gouge(bowl, CUTTERS[2], u, v, (0.6, 0.8, 0.0), lead, tilt)
        assert np.all(got < 1e-9)
    assert np.all(_gouge(bowl, CUTTERS[0], u, v, (0.6, 0.8, 0.0), 4.0, 2.0) > 0.5)


def test_the_tangent_placement_in_the_loop_is_cutter_cc_to_tip():
    bump = Sphere(60.0, sign=1.0, half=30.0)
    rng = np.random.default_rng(3)
    u, v = rng.uniform(0.2, 0.8, 20), rng.uniform(0.2, 0.8, 20)
    trough = Cylinder(40.0, axis="x", sign=-1.0, half=20.0)
    for surface in (bump, trough):
        for cutter in CUTTERS:
            args = (surface, cutter, u, v, (0.8, 0.6, 0.0), 4.0, 1.5)
            np.testing.assert_allclose(_gouge(*args), _gouge(*args, tip=True), atol=1e-12)


def _trough_net(rho, half, width):
    """Bezier net (2 x 4 poles) of a concave cylinder of radius rho whose axis is along Y, so
    that passes fed along X cross its curvature: the cubic arc over [-half, half] radians."""
    k = 4.0 / 3.0 * np.tan(half / 2.0) * rho
    s, c = np.sin(half), np.cos(half)
    pts = [(-rho * s, rho - rho * c), (-rho * s + k * c, rho - rho * c - k * s),
           (rho * s - k * c, rho - rho * c - k * s), (rho * s, rho - rho * c)]
    return [[[x, y, z] for x, z in pts] for y in (0.0, width)]


@pytest.mark.parametrize("rho, tool", [(150.0, 3), (100.0, 6)])  # flat D16; torus D16 r3
def test_analytic_gouge_on_a_trough_along_the_feed_matches_the_cut_simulation(rho, tool):
    pr = ToolpathProblem(surface={"type": "bezier", "poles": _trough_net(rho, 0.35, 40.0)},
                         normalization=NORM)
    params = dict(tool=tool, stepover=30, lead=2.0, tilt=0.0, step=5)
    crit = pr.evaluate_params(params)
    sim = simulate(pr.cl_path(params)[0], pr.surface, 0.2).metrics["gouge_max_mm"]
    assert sim > 0.1
    assert crit["gouge_max"] == pytest.approx(sim, rel=0.15)
    assert crit["machining_error"] >= crit["gouge_max"]
    if tool == 3:  # the flat end's heel: the closed form (the Bezier arc is nearly circular)
        assert crit["gouge_max"] == pytest.approx(_heel_closed_form(8.0, rho, 2.0), rel=0.05)


def test_fountas_leaned_flat_end_gouge_matches_the_cut_simulation():
    # the best plan of runs/fountas_toolpath_zoned_vega.yaml: flat D16, one zone fed at
    # 168 deg; the gap model alone said 0.053 mm, the simulation 0.221 mm (grid 0.2 mm),
    # the deepest cut about 6 mm behind and 8 mm beside the contact
    tools = [{"id": 3, "type": "flat", "diameter": 16}]
    pr = ToolpathProblem(tools=tools, feed_angle=168.0, normalization=NORM)
    params = dict(tool=3, stepover=43.721, lead=4.366, tilt=0.028, step=9.411)
    crit = pr.evaluate_params(params)
    sim = simulate(pr.cl_path(params)[0], pr.surface, 0.2).metrics["gouge_max_mm"]
    assert sim > 0.15
    assert crit["gouge_max"] == pytest.approx(sim, rel=0.15)
