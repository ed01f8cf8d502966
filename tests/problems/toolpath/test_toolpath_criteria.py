"""Criteria of whole toolpaths on surfaces with hand-computable answers (the one engine:
single-zone plans of the ``Planner`` judged by ``analytic_criteria``)."""

import numpy as np
import pytest
from toolpath_analytic import Cylinder, Plane, Sphere

from engine_rows import criteria, heights

from evoplan.problems.toolpath.criteria.scallop import scallop_height

BALL8 = [{"id": 1, "diameter": 8, "corner_radius": 4}]
FLAT12 = [{"id": 1, "diameter": 12, "corner_radius": 0}]


def _x(stepover, lead=0.0, tilt=0.0, step=8.0, tool=0):
    return np.array([[tool, stepover, lead, tilt, step]], float)


def test_plane_ball_end_scallop_chord_length_and_time():
    plane = Plane(0.0, 100.0, 0.0, 60.0)
    c = criteria(plane, BALL8, _x(37.5, step=7.0), feed_rate=1000.0)  # 3 mm step-over: 20 equal gaps over 60 mm
    s, R = 3.0, 4.0
    assert c["n_passes"][0] == 21
    assert c["chord_error_max"][0] < 1e-9
    assert c["scallop_max"][0] == pytest.approx(R - np.sqrt(R * R - s * s / 4), rel=1e-4)
    assert c["machining_error"][0] == pytest.approx(c["scallop_max"][0], abs=1e-9)
    assert c["gouge_max"][0] == 0.0
    assert c["cc_count"][0] == 21 * (np.ceil(100 / 7.0) + 1)
    assert c["cutting_length"][0] == pytest.approx(21 * 100.0)
    assert c["link_length"][0] == pytest.approx(60.0)
    assert c["machining_time_nominal"][0] == pytest.approx(2160.0 / 1000.0)


def test_slope_across_the_feed_widens_the_surface_spacing():
    b = 0.75  # z = 0.75 y: 36.87 deg across an X feed
    c = criteria(Plane(0.0, 100.0, 0.0, 60.0, b=b), BALL8, _x(37.5))
    w = 3.0 * np.sqrt(1 + b * b)  # the CC points are 3.75 mm apart on the surface
    assert c["scallop_max"][0] == pytest.approx(4.0 - np.sqrt(16.0 - w * w / 4), rel=1e-4)


def test_flat_end_effective_radius_and_elliptic_scallop_on_a_plane():
    lead = 3.0
    c = criteria(Plane(0.0, 100.0, 0.0, 60.0), FLAT12, _x(25.0, lead=lead))  # 3 mm
    R, a = 6.0, np.radians(lead)
    assert c["r_eff"][0] == pytest.approx(R / np.sin(a), rel=1e-12)
    ellipse = R * np.sin(a) * (1 - np.sqrt(1 - 1.5 ** 2 / R ** 2))
    assert c["scallop_max"][0] == pytest.approx(ellipse, rel=1e-3)
    assert c["undercut_max"][0] == c["scallop_max"][0]  # a flat-end's scallop is its undercut


def test_flat_end_at_lead_zero_is_finite_and_leaves_no_scallop_on_a_plane():
    c = criteria(Plane(0.0, 100.0, 0.0, 60.0), FLAT12, _x(25.0))
    assert np.isposinf(c["r_eff"][0])  # the flat bottom cuts
    assert c["scallop_max"][0] == 0.0 and c["gouge_max"][0] == 0.0
    for k, v in c.items():
        if k != "r_eff":
            assert np.isfinite(v[0]), k


def test_stepover_wider_than_the_tool_leaves_the_allowance():
    c = criteria(Plane(0.0, 100.0, 0.0, 60.0), BALL8, _x(150.0), allowance=0.3)  # 12 mm passes with an 8 mm ball: uncut strips
    assert c["scallop_max"][0] == pytest.approx(0.3)
    assert np.isfinite(c["machining_error"][0])


def _plane_d(pb):
    """Per point its plane's offset, and the sorted plane offsets (one section per plane)."""
    return pb.sec_d[pb.pt_sec], pb.sec_d[np.argsort(pb.sec_pass)]


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_cylinder_across_the_feed_convex_and_concave_scallops(sign):
    rho, R = 60.0, 4.0
    cyl = Cylinder(rho, axis="x", sign=sign, half=25.0, length=60.0)  # curved across an X feed
    pb, pt = heights(cyl, BALL8, _x(25.0))  # 2 mm XY spacing
    d, planes = _plane_d(pb)
    # exact: two ball circles on a circular section, CC points a chord w apart
    nxt = d < planes.max() - 1e-9
    w_exact = np.abs(np.diff(planes))[pb.sec_pass[pb.pt_sec[nxt]]] / np.abs(pt["normal"][nxt, 2])
    expected = scallop_height(R, w_exact, sign * -1.0 / rho)  # bump: convex (kappa < 0)
    np.testing.assert_allclose(pt["kappa"][nxt], -sign / rho, rtol=1e-9)
    # model: surface to second order around each contact, spacing to first order (0.5 % here)
    np.testing.assert_allclose(pt["h"][nxt], expected, rtol=0.01)
    flat = 4.0 - np.sqrt(16.0 - w_exact ** 2 / 4)
    assert np.all(pt["h"][nxt] > flat) if sign > 0 else np.all(pt["h"][nxt] < flat)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_sphere_cap_and_bowl_scallops_and_chord_errors(sign):
    rho, R = 80.0, 4.0
    pb, pt = heights(Sphere(rho, sign=sign, half=20.0), BALL8, _x(25.0, step=5.0))
    d, planes = _plane_d(pb)
    nxt = d < planes.max() - 1e-9
    # across the feed the sphere curves with 1/rho everywhere; the spacing on the surface
    # is the XY spacing over the cross-feed cosine of the slope
    np.testing.assert_allclose(pt["kappa"], -sign / rho, rtol=1e-6)
    expected = scallop_height(R, pt["w"][nxt], -sign / rho)
    np.testing.assert_allclose(pt["h"][nxt], expected, rtol=0.005)  # parabolic surface term
    # a pass at y = d is a circle of radius sqrt(rho^2 - d^2): the sagitta of each chord
    r_sec = np.sqrt(rho ** 2 - pb.sec_d[pb.seg_sec] ** 2)
    L = pb.seg_len
    np.testing.assert_allclose(pb.seg_err, r_sec - np.sqrt(r_sec ** 2 - L ** 2 / 4), rtol=1e-5)


def test_flat_tool_on_a_concave_section_gouges_and_a_ball_does_not():
    trough = Cylinder(50.0, axis="x", sign=-1.0, half=20.0, length=60.0)
    tools = FLAT12 + [{"id": 2, "diameter": 8, "corner_radius": 4}]
    X = np.vstack([_x(25.0, lead=3.0, tool=0), _x(37.5, lead=3.0, tool=1)])
    c = criteria(trough, tools, X)
    # flat-end, R_eff = 6 / sin 3 deg = 114.6 mm > rho = 50: flatter than the section
    assert c["gouge_max"][0] > 0 and c["scallop_max"][0] == 0
    assert c["gouge_max"][1] == 0 and c["scallop_max"][1] > 0
    w = 3.0  # the trough's bottom: ~ (w^2 / 8)(1 / R - 1 / rho), concave formula
    assert c["scallop_max"][1] >= scallop_height(4.0, w, 1 / 50.0)


def test_flat_end_tilted_across_the_feed_leaves_an_undercut():
    c = criteria(Plane(0.0, 100.0, 0.0, 60.0), FLAT12, _x(25.0, lead=0.0, tilt=1.0))  # 3 mm, rim-only cutting
    assert c["r_eff"][0] == 0.0
    # worst gap: the rim's side, covered by the passes one further out, 1.5 w from them
    assert c["undercut_max"][0] == pytest.approx(4.5 * np.tan(np.radians(1.0)), rel=1e-3)
