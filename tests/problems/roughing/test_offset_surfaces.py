"""Normal offsets: the distance is exact on a sphere and a cylinder, folds are flagged."""

import numpy as np
import pytest

from evoplan.problems.toolpath.roughing.offset import normal_offset
from evoplan.problems.toolpath.geometry.surface import Jet, Surface


class Sphere(Surface):
    """Cap of a sphere (centre c, radius R): theta = 2 pi u, phi = 0.2 + v."""

    def __init__(self, c, radius, normal_sign=None):
        self.c, self.r = np.asarray(c, float), radius
        self._orient(normal_sign)

    def jet(self, u, v, order=2):
        t, p = 2 * np.pi * np.asarray(u), 0.2 + np.asarray(v)
        ct, st, cp, sp = np.cos(t), np.sin(t), np.cos(p), np.sin(p)
        z = np.zeros_like(t)
        r, w = self.r, 2 * np.pi
        pt = self.c + r * np.column_stack([ct * sp, st * sp, cp])
        su = r * w * np.column_stack([-st * sp, ct * sp, z])
        sv = r * np.column_stack([ct * cp, st * cp, -sp])
        suu = r * w * w * np.column_stack([-ct * sp, -st * sp, z])
        suv = r * w * np.column_stack([-st * cp, ct * cp, z])
        svv = r * np.column_stack([-ct * sp, -st * sp, -cp])
        return Jet(pt, su, sv, suu, suv, svv)


class Cylinder(Surface):
    """Cylinder of radius R about the X axis: x = 50 u, angle a = v - 0.5 from +Z."""

    def __init__(self, radius, normal_sign=None):
        self.r = radius
        self._orient(normal_sign)

    def jet(self, u, v, order=2):
        a = np.asarray(v) - 0.5
        z = np.zeros_like(a)
        r = self.r
        pt = np.column_stack([50 * np.asarray(u), r * np.sin(a), r * np.cos(a)])
        su = np.column_stack([50 + z, z, z])
        sv = r * np.column_stack([z, np.cos(a), -np.sin(a)])
        svv = r * np.column_stack([z, -np.sin(a), -np.cos(a)])
        return Jet(pt, su, sv, np.zeros_like(su), np.zeros_like(su), svv)


UV = np.random.default_rng(0).uniform(0, 1, (2, 500))


@pytest.mark.parametrize("d", [0.5, 6.0, 17.25])
def test_offset_of_a_sphere_is_the_concentric_sphere(d):
    out = normal_offset(Sphere([1, 2, 3], 10.0), *UV, d)   # convex seen from the tool: never folds
    np.testing.assert_allclose(np.linalg.norm(out.points - [1, 2, 3], axis=1), 10.0 + d, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(out.points - out.foot, axis=1), d, atol=1e-6)
    assert not out.folded.any()


def test_offset_inside_a_sphere_folds_past_its_radius():
    outside = Sphere([0, 0, 0], 10.0)
    inside = Sphere([0, 0, 0], 10.0, normal_sign=-outside.normal_sign)  # tool in the bowl: kappa = 1/R
    small, big = normal_offset(inside, *UV, 6.0), normal_offset(inside, *UV, 12.0)
    np.testing.assert_allclose(np.linalg.norm(small.points, axis=1), 4.0, atol=1e-6)
    assert not small.folded.any() and big.folded.all()


@pytest.mark.parametrize("d", [0.3, 4.0])
def test_offset_of_a_cylinder_keeps_its_axis(d):
    for sign, expect in ((1.0, 8.0 + d), (-1.0, 8.0 - d)):
        out = normal_offset(Cylinder(8.0, normal_sign=sign), *UV, d)
        np.testing.assert_allclose(np.hypot(out.points[:, 1], out.points[:, 2]), expect, atol=1e-6)
        np.testing.assert_allclose(out.points[:, 0], out.foot[:, 0], atol=1e-9)
        assert not out.folded.any()
    assert normal_offset(Cylinder(8.0, normal_sign=-1.0), *UV, 8.5).folded.all()
    # the convex side folds only for an offset to the other side past the radius
    assert normal_offset(Cylinder(8.0), *UV, -8.5).folded.all()
    assert not normal_offset(Cylinder(8.0), *UV, 8.5).folded.any()
