"""Surfaces: Fountas Eq. 14 reference geometry, Choi's net, Bezier/B-spline, curvatures."""

import numpy as np
import pytest
from toolpath_analytic import Cylinder, Sphere
from scipy.integrate import simpson

from evoplan.problems.toolpath import BezierSurface, BSplineSurface, choi_surface, fountas_surface
from evoplan.problems.toolpath.geometry.bezier import choi_poles


def _grid(n):
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    return u.ravel(), v.ravel()


def test_fountas_bounding_box_area_and_slope_match_reference():
    s = fountas_surface()
    u, v = _grid(401)
    j = s.jet(u, v)
    lo, hi = j.p.min(0), j.p.max(0)
    # docs/toolpath_formulas.md: x in [-94.4, 0.1], y in [-103.2, 0], z in [3.63, 49.8]
    np.testing.assert_allclose(lo, [-94.4, -103.2, 3.63], atol=0.005)
    np.testing.assert_allclose(hi, [0.1, 0.0, 49.8], atol=0.005)
    area = np.linalg.norm(np.cross(j.su, j.sv), axis=1).reshape(401, 401)
    x = np.linspace(0, 1, 401)
    assert simpson(simpson(area, x=x), x=x) == pytest.approx(11109, abs=1.0)  # "about 11 109"
    n = s.normals(u, v)
    assert np.degrees(np.arccos(n[:, 2].min())) == pytest.approx(53.5, abs=0.05)


def test_fountas_slope_and_cross_feed_curvature_at_0p7_0p5():
    s = fountas_surface()
    n = s.normals(0.7, 0.5)[0]
    assert np.degrees(np.arccos(n[2])) == pytest.approx(28.5, abs=0.05)
    # across an X feed: the pass y = const is an iso-u curve, its tangent is S_v
    sv = s.jet(np.array([0.7]), np.array([0.5])).sv[0]
    across = np.cross(n, sv / np.linalg.norm(sv))
    k = s.normal_curvature(0.7, 0.5, across[None])[0]
    assert k == pytest.approx(0.0159, abs=0.00005)  # > 0: concave seen from the tool


def test_choi_net_bounds_and_symmetry():
    s = choi_surface()
    u, v = _grid(201)
    p = s.points(u, v)
    np.testing.assert_allclose(p.min(0)[:2], [0, 0], atol=1e-12)
    np.testing.assert_allclose(p.max(0)[:2], [50.8, 76.2], atol=1e-12)
    assert 24.0 <= p[:, 2].min() < 25.0 and p[:, 2].max() == pytest.approx(38.1)
    mirrored = s.points(u, 1 - v)
    np.testing.assert_allclose(mirrored[:, 2], p[:, 2], atol=1e-12)  # symmetric about v = 0.5
    np.testing.assert_allclose(mirrored[:, 1], 76.2 - p[:, 1], atol=1e-12)


def test_bezier_corners_interpolate_poles_and_derivatives_match_finite_differences():
    rng = np.random.default_rng(3)
    poles = rng.normal(size=(4, 3, 3)) * 10
    s = BezierSurface(poles)
    corners = s.points([0, 1, 0, 1], [0, 0, 1, 1])
    np.testing.assert_allclose(corners, poles[[0, -1, 0, -1], [0, 0, -1, -1]], atol=1e-10)
    u, v = rng.random(50), rng.random(50)
    j = s.jet(u, v)
    h = 1e-5
    fd = lambda du, dv: (s.points(u + du, v + dv) - s.points(u - du, v - dv)) / (2 * h)
    np.testing.assert_allclose(j.su, fd(h, 0), atol=1e-5)
    np.testing.assert_allclose(j.sv, fd(0, h), atol=1e-5)
    ju, jv = s.jet(u + h, v), s.jet(u - h, v)
    np.testing.assert_allclose(j.suu, (ju.su - jv.su) / (2 * h), atol=1e-4)
    np.testing.assert_allclose(j.suv, (ju.sv - jv.sv) / (2 * h), atol=1e-4)


def test_single_span_clamped_bspline_equals_the_bezier_of_the_same_net():
    b = choi_surface()
    s = BSplineSurface(choi_poles(), (3, 3))
    u, v = _grid(31)
    for a, c in zip(s.jet(u, v), b.jet(u, v)):
        np.testing.assert_allclose(a, c, atol=1e-9)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_cylinder_and_sphere_curvatures_are_plus_minus_one_over_rho(sign):
    rho = 40.0
    cyl = Cylinder(rho, axis="y", sign=sign)
    u, v = np.array([0.2, 0.5, 0.8]), np.array([0.3, 0.5, 0.9])
    kmin, kmax = cyl.principal_curvatures(u, v)
    # bump (sign +1) is convex seen from above: curvature -1/rho; trough: +1/rho
    np.testing.assert_allclose(np.where(sign > 0, kmin, kmax), -sign / rho, rtol=1e-9)
    np.testing.assert_allclose(np.where(sign > 0, kmax, kmin), 0.0, atol=1e-12)
    along_axis = np.tile([0.0, 1.0, 0.0], (3, 1))
    np.testing.assert_allclose(cyl.normal_curvature(u, v, along_axis), 0.0, atol=1e-12)
    sph = Sphere(rho, sign=sign)
    kmin, kmax = sph.principal_curvatures(u, v)
    # umbilic: the discriminant H^2 - K is ~0, its square root amplifies round-off to ~1e-8
    np.testing.assert_allclose(kmin, -sign / rho, rtol=1e-6)
    np.testing.assert_allclose(kmax, -sign / rho, rtol=1e-6)


def test_normal_curvature_obeys_euler_between_the_principal_values():
    s = fountas_surface()
    rng = np.random.default_rng(0)
    u, v = rng.random(200), rng.random(200)
    j = s.jet(u, v)
    kmin, kmax = s.principal_curvatures(u, v)
    d = rng.normal(size=(200, 3))
    k = s.normal_curvature(u, v, d)
    assert np.all(k >= kmin - 1e-12) and np.all(k <= kmax + 1e-12)
    # along su and sv the normal curvature is L/E and N/G
    n = s.normals(u, v)
    L = np.einsum("ij,ij->i", j.suu, n) / np.einsum("ij,ij->i", j.su, j.su)
    np.testing.assert_allclose(s.normal_curvature(u, v, j.su), L, rtol=1e-9)


def test_unit_normal_is_numpys_cross_and_norm_bit_for_bit():
    from types import SimpleNamespace

    from evoplan.problems.toolpath.geometry.surface import unit_normal

    rng = np.random.default_rng(11)
    for shape in ((1, 3), (257, 3), (4, 5, 3)):
        su, sv = rng.normal(size=shape), rng.normal(size=shape)
        for sign in (1.0, -1.0):
            ref = np.cross(su, sv) * sign
            ref = ref / np.linalg.norm(ref, axis=-1, keepdims=True)
            got = unit_normal(SimpleNamespace(su=su, sv=sv), sign)
            assert got.shape == ref.shape and np.array_equal(got, ref)
    # a real surface's jets, Choi's, on its whole parameter square
    surface = choi_surface()
    u, v = rng.uniform(0, 1, (2, 500))
    jet = surface.jet(u, v, order=1)
    ref = np.cross(jet.su, jet.sv) * surface.normal_sign
    assert np.array_equal(unit_normal(jet, surface.normal_sign),
                          ref / np.linalg.norm(ref, axis=-1, keepdims=True))
