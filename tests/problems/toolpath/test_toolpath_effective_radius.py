"""Effective radius: reference numbers of docs/toolpath_formulas.md and the classic cases."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from evoplan.problems.toolpath import fountas_surface
from evoplan.problems.toolpath.cutters.effective_radius import (
    effective_radius, effective_radius_3axis, effective_radius_fountas_eq4,
    effective_radius_lead_tilt,
)
from evoplan.problems.toolpath.cutters.silhouette import profile_tables

deg = np.radians


def test_ball_end_effective_radius_is_its_radius_for_any_orientation():
    lead = deg(np.linspace(0, 10, 7))
    tilt = deg(np.linspace(0, 5, 7))
    np.testing.assert_allclose(effective_radius_lead_tilt(6.0, 6.0, lead, tilt), 6.0)


def test_flat_end_at_tilt_zero_is_r_over_sin_lead():
    lead = deg(np.array([0.5, 1.0, 3.0, 5.0, 30.0]))
    np.testing.assert_allclose(effective_radius_lead_tilt(6.0, 0.0, lead, 0.0), 6.0 / np.sin(lead))


def test_lead_tilt_reference_values_and_eq4_as_printed():
    # flat-end R = 6 mm: (lead, tilt) = (3, 1), (2, 2), (5, 0) degrees
    lead, tilt = deg(np.array([3.0, 2.0, 5.0])), deg(np.array([1.0, 2.0, 0.0]))
    np.testing.assert_allclose(effective_radius_lead_tilt(6.0, 0.0, lead, tilt),
                               [97.91, 60.84, 68.84], atol=0.005)
    np.testing.assert_allclose(effective_radius_fountas_eq4(6.0, 0.0, lead, tilt),
                               [114.61, 171.71, 68.84], atol=0.005)


def test_djebali_eq1_reference_values_at_fountas_0p7_0p5():
    n = fountas_surface().normals(0.7, 0.5)[0]
    slope, phi = np.arccos(n[2]), np.arctan2(n[1], n[0])
    feed = deg(np.array([0.0, 90.0]))
    np.testing.assert_allclose(effective_radius_3axis(6.0, 0.0, slope, feed, phi),
                               [1.4796, 11.6656], atol=5e-5)
    np.testing.assert_allclose(effective_radius_3axis(6.0, 2.0, slope, feed, phi),
                               [2.9864, 9.7771], atol=5e-5)


def test_general_form_equals_djebali_eq1_with_the_section_tangent():
    s = fountas_surface()
    rng = np.random.default_rng(1)
    u, v = rng.random(20), rng.random(20)
    n = s.normals(u, v)
    alpha = rng.uniform(0, np.pi, 20)
    h = np.stack([np.cos(alpha), np.sin(alpha), 0 * alpha], -1)
    c = np.cross([0.0, 0.0, 1.0], h)  # normal of the vertical cutting plane
    t = np.cross(c, n)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    general = effective_radius(6.0, 2.0, t[:, 2], n[:, 2])  # tool axis a = z
    eq1 = effective_radius_3axis(6.0, 2.0, np.arccos(n[:, 2]), alpha, np.arctan2(n[:, 1], n[:, 0]))
    np.testing.assert_allclose(general, eq1, rtol=1e-9)


def test_degenerate_orientations_are_guarded():
    with np.errstate(all="raise"):
        flat_bottom = effective_radius_lead_tilt(np.array([6.0, 6.0]), np.array([0.0, 2.0]), 0.0, 0.0)
        rim_only = effective_radius_lead_tilt(np.array([6.0, 6.0]), np.array([0.0, 2.0]), 0.0, deg(1.0))
        horizontal = effective_radius_3axis(6.0, 2.0, 0.0, 0.0, 0.0)
    assert np.all(np.isposinf(flat_bottom))
    np.testing.assert_allclose(rim_only, [0.0, 2.0])  # the rim (or the corner) cuts
    assert np.isposinf(horizontal)
    assert effective_radius_lead_tilt(6.0, 6.0, 0.0, 0.0) == 6.0  # a ball stays a ball


@settings(max_examples=40, deadline=None)
@given(tool=st.sampled_from([(4, 0), (6, 0), (8, 0), (4, 1), (6, 2), (8, 3), (4, 4), (8, 8)]),
       lead=st.floats(0.3, 5.0), tilt=st.floats(0.0, 2.0))
def test_projected_profile_curvature_at_the_contact_is_r_eff(tool, lead, tilt):
    R, r = tool
    expected = effective_radius_lead_tilt(R, r, deg(lead), deg(tilt))
    # the table's samples are exact outline points; a finely sampled table resolves the
    # contact's neighbourhood, which shrinks with R_eff (tilt >> lead: the contact sits near
    # the end of a thin rotated ellipse, whose curvature changes over a short distance)
    x, z, _ = profile_tables(np.array([R]), np.array([r]), deg(np.array([lead])),
                             deg(np.array([tilt])), m_fine=4001)
    xs, zs = np.r_[x[0], -x[1]], np.r_[z[0], z[1]]
    near = (xs != 0) & (np.abs(xs) < min(R, expected) / 200)
    assert near.sum() >= 10
    fit = np.linalg.lstsq(np.stack([xs[near] ** 2, xs[near] ** 3, xs[near] ** 4], 1), zs[near],
                          rcond=None)[0]
    assert 1 / (2 * fit[0]) == pytest.approx(expected, rel=2e-3)
