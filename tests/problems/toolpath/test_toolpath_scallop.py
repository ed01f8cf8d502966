"""Scallop: circle formulas, Djebali Eq. 2 references, the projected-profile model."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from evoplan.problems.toolpath.cutters.silhouette import profile_tables
from evoplan.problems.toolpath.cutters.effective_radius import effective_radius_lead_tilt
from evoplan.problems.toolpath.criteria.scallop import (
    flat_scallop, gap_heights, profile_height, scallop_height, spacing_exact,
    spacing_flat_approx, stepover_djebali_eq2,
)

deg = np.radians


def _circle_cusp(R, w, kappa):
    """Independent cusp: intersect the two tool circles numerically (bisection on the
    bisector) in the frame of a surface circle of curvature kappa (> 0 concave)."""
    th = np.arcsin(w * kappa / 2)
    cc = np.array([np.sin(th) / kappa, (1 - np.cos(th)) / kappa])
    nrm = np.array([-np.sin(th), np.cos(th)])
    centre = cc + R * nrm
    lo, hi = -R, R  # the lower intersection of the circle with x = 0
    f = lambda zz: centre[0] ** 2 + (zz - centre[1]) ** 2 - R * R
    for _ in range(200):
        mid = (lo + hi) / 2
        if (mid < centre[1]) and f(mid) > 0:
            lo = mid
        else:
            hi = mid
    return (lo + hi) / 2


def test_flat_scallop_formula():
    R, w = 6.0, np.array([0.5, 2.0, 4.0, 11.9])
    np.testing.assert_allclose(flat_scallop(R, w), R - np.sqrt(R * R - w * w / 4), rtol=1e-12)
    assert flat_scallop(np.inf, 3.0) == 0.0
    np.testing.assert_allclose(scallop_height(R, w, 0.0), flat_scallop(R, w), rtol=1e-12)


@pytest.mark.parametrize("kappa", [-1 / 30, -1 / 100, 1 / 100, 1 / 30])
def test_circle_scallop_is_exact_against_a_numerical_intersection(kappa):
    for w in (0.6, 2.0, 5.0):
        assert scallop_height(6.0, w, kappa) == pytest.approx(_circle_cusp(6.0, w, kappa), abs=1e-9)


def test_circle_scallop_first_order_forms_convex_concave_and_flat_bottom():
    R, rho, w = 6.0, 30.0, 0.3
    assert scallop_height(R, w, -1 / rho) == pytest.approx(w * w / 8 * (1 / R + 1 / rho), rel=1e-3)
    assert scallop_height(R, w, 1 / rho) == pytest.approx(w * w / 8 * (1 / R - 1 / rho), rel=1e-3)
    # flat bottom (R_eff = inf): convex leaves w^2/(8 rho), concave gouges as much
    assert scallop_height(np.inf, w, -1 / rho) == pytest.approx(w * w / (8 * rho), rel=1e-3)
    assert scallop_height(np.inf, w, 1 / rho) == pytest.approx(-w * w / (8 * rho), rel=1e-3)


def test_djebali_spacing_reference_values():
    # docs/toolpath_formulas.md: R_eff 6, rho 30, h 0.01 (convex)
    assert stepover_djebali_eq2(0.01, 6.0, 30.0) == pytest.approx(0.7589, abs=5e-5)
    centres, cc = spacing_exact(0.01, 6.0, 30.0, convex=True)
    assert centres == pytest.approx(0.7585, abs=5e-5)
    assert cc == pytest.approx(0.6321, abs=5e-5)
    assert spacing_flat_approx(0.01, 6.0) == pytest.approx(0.6928, abs=5e-5)
    # and the exact spacing is consistent with the exact cusp height, convex and concave
    assert scallop_height(6.0, cc, -1 / 30) == pytest.approx(0.01, rel=1e-4)
    _, cc_concave = spacing_exact(0.01, 6.0, 30.0, convex=False)
    assert scallop_height(6.0, cc_concave, 1 / 30) == pytest.approx(0.01, rel=1e-4)
    assert cc_concave > spacing_flat_approx(0.01, 6.0) > cc  # concave allows wider passes


def test_ball_profile_reproduces_the_flat_formula():
    R = np.array([4.0, 6.0, 8.0])
    tab = profile_tables(R, R, deg(np.array([0.0, 3.0, 5.0])), deg(np.array([0.0, 1.0, 2.0])))
    for w in (1.6, 3.0, 5.0, 7.0):
        h = profile_height(tab, np.array([0, 2, 4]), np.full(3, w / 2))
        np.testing.assert_allclose(h, flat_scallop(R, w), rtol=1e-3)


def test_flat_end_profile_at_tilt_zero_is_the_exact_ellipse_and_tends_to_r_eff():
    R, lead = 6.0, deg(3.0)
    tab = profile_tables(np.array([R]), np.array([0.0]), np.array([lead]), np.array([0.0]))
    x = np.array([0.5, 1.0, 2.0, 4.0])
    ellipse = R * np.sin(lead) * (1 - np.sqrt(1 - x * x / (R * R)))
    np.testing.assert_allclose(profile_height(tab, np.zeros(4, int), x), ellipse, rtol=1e-3)
    # the R_eff circle is the osculating circle: close for small x, below the ellipse further out
    circle = flat_scallop(R / np.sin(lead), 2 * x)
    assert abs(ellipse[0] / circle[0] - 1) < 0.01 and ellipse[-1] > 1.05 * circle[-1]


def _brute_profile(R, r, lead, tilt, xq):
    """Independent lower envelope of the tool projected along the feed t.

    The torus's silhouette is where its normal N = cos(psi) radial(theta) + sin(psi) a is
    perpendicular to t; on the lower side N.n < 0. That curve (sampled densely in theta)
    and the bottom disk's projected ellipse are intersected with the verticals b = x and
    the lowest crossing is taken. Returns (heights on the +b side, on the -b side)."""
    a = np.array([np.sin(lead), np.cos(lead) * np.sin(tilt), np.cos(lead) * np.cos(tilt)])
    e1 = np.array([1.0, 0, 0]) - a[0] * a
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    th = np.linspace(0, 2 * np.pi, 200001)
    radial = np.outer(np.cos(th), e1) + np.outer(np.sin(th), e2)
    c, s = a[0] * np.ones_like(th), -radial[:, 0]  # (cos psi, sin psi) ~ (a.t, -radial.t)
    nn = np.hypot(c, s)
    c, s = c / nn, s / nn
    N = c[:, None] * radial + s[:, None] * a
    flip = N[:, 2] > 0
    N[flip] *= -1
    sil = (R - r) * radial + r * N  # silhouette points (t, b, n)
    curves = [sil[:, 1:]]
    if r < R:  # bottom disk at -r a: lowest point of its projected ellipse at b = x
        xs = np.linspace(-R, R, 200001)
        m1 = (R - r) * np.array([e1[1], e2[1]])
        m2 = (R - r) * np.array([e1[2], e2[2]])
        m1n = np.linalg.norm(m1)
        if m1n > 1e-12:
            p = np.array([-m1[1], m1[0]]) / m1n
            dx = xs + r * a[1]
            ok = np.abs(dx) <= m1n
            zz = (-r * a[2] + dx * (m2 @ m1) / m1n ** 2
                  - abs(m2 @ p) * np.sqrt(np.clip(1 - (dx / m1n) ** 2, 0, 1)))
            curves.append(np.stack([xs[ok], zz[ok]], -1))

    def env(x):  # lowest crossing of every curve with b = x
        out = np.full(x.shape, np.inf)
        for cv in curves:
            b0, b1, n0, n1 = cv[:-1, 0], cv[1:, 0], cv[:-1, 1], cv[1:, 1]
            for i, xi in enumerate(x):
                hit = (b0 - xi) * (b1 - xi) <= 0
                if hit.any():
                    f = np.where(b1[hit] != b0[hit], (xi - b0[hit]) / (b1[hit] - b0[hit] + 1e-300), 0)
                    out[i] = min(out[i], np.min(n0[hit] + f * (n1[hit] - n0[hit])))
        return out

    allpts = np.concatenate(curves)
    i0 = np.argmin(allpts[:, 1])
    b_c, n_c = allpts[i0]
    return env(b_c + xq) - n_c, env(b_c - xq) - n_c


@settings(max_examples=10, deadline=None)
@given(tool=st.sampled_from([(6, 0), (8, 0), (6, 2), (8, 3), (4, 1), (6, 6)]),
       lead=st.floats(0.5, 5.0), tilt=st.floats(0.0, 2.0))
def test_profile_model_matches_an_independent_projection_of_the_tool(tool, lead, tilt):
    R, r = tool
    tab = profile_tables(np.array([R]), np.array([r]), deg(np.array([lead])), deg(np.array([tilt])))
    xq = np.array([0.8, 1.6, 2.4, 3.6])
    right, left = _brute_profile(R, r, deg(lead), deg(tilt), xq)
    got_r = profile_height(tab, np.zeros(4, int), xq)
    got_l = profile_height(tab, np.ones(4, int), xq)
    # within 0.02 mm of the reach the profile rises vertically (the rim): there a 1e-4 mm
    # difference in x is a large one in z, so those queries only have to agree on "beyond"
    # rtol: the table's linear interpolation between its samples; the worst case found is
    # 0.39 % (0.25 um of 0.064 mm: torus D16 r3, lead 0.64 deg, tilt 0.5 deg, 2.4 mm out),
    # 0.25 % on a 6 x 10 x 5 grid of the cases drawn here; twice the uniform samples
    # (profile_tables' m_uniform 128) would halve it, and move every 5-axis analytic scallop
    # by up to 0.2 %
    for got, ref, reach in ((got_r, right, tab[2][0]), (got_l, left, tab[2][1])):
        ok = np.abs(xq - reach) > 0.02
        np.testing.assert_allclose(got[ok], ref[ok], rtol=4.5e-3, atol=3e-5)
        assert np.array_equal(np.isinf(got), xq > reach * (1 + 1e-12))


def test_flat_bottom_leaves_no_scallop_on_a_plane_and_gouges_a_concave_section():
    tab = profile_tables(np.array([6.0]), np.array([0.0]), np.zeros(1), np.zeros(1))
    ind, side = np.zeros(3, int), np.array([1, -1, 1])
    h = gap_heights(tab, ind, side, np.array([2.0, 4.0, 4.0]), np.array([0.0, 0.0, 0.01]), 0.5)
    assert h[0] == 0.0 and h[1] == 0.0
    # concave: the flat bottom of the pass one further out digs deepest at the gap middle
    assert h[2] == pytest.approx(-0.01 * (1.5 * 4.0) ** 2 / 2)


def test_flat_end_tilted_across_the_feed_leaves_a_saw_tooth_undercut():
    tilt = deg(2.0)
    tab = profile_tables(np.array([6.0]), np.array([0.0]), np.zeros(1), np.array([tilt]))
    assert effective_radius_lead_tilt(6.0, 0.0, 0.0, tilt) == 0.0  # the circle model has nothing
    w = np.array([3.0, 3.0])
    h = gap_heights(tab, np.zeros(2, int), np.array([1, -1]), w, np.zeros(2), 0.5)
    # gap on the bottom's side: the two inclined bottoms meet at w/2; on the rim's side the
    # passes one further out cover it, meeting at 3w/2
    np.testing.assert_allclose(np.sort(h), np.sort([1.5 * np.tan(tilt), 4.5 * np.tan(tilt)]), rtol=1e-3)


def test_stepover_wider_than_the_tool_leaves_the_allowance():
    tab = profile_tables(np.array([4.0, 4.0]), np.array([4.0, 0.0]), np.zeros(2), np.zeros(2))
    h = gap_heights(tab, np.array([0, 1]), np.array([1, 1]), np.array([9.0, 17.0]), np.zeros(2), 0.3)
    np.testing.assert_allclose(h, 0.3)
    assert np.all(np.isfinite(h))
