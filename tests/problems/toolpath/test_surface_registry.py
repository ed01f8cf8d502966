"""The surface registry: per-type settings models, unknown keys, the union, NURBS partials."""

import numpy as np
import pytest

from evoplan.problems.toolpath.geometry.registry import SURFACES, surface_union
from evoplan.problems.toolpath.geometry.spec import parse_surface

R, L = 20.0, 30.0
W = np.sqrt(0.5)  # cos 45 deg: the middle weight of a 90-degree arc


def _arc_poles():
    """Quarter circle of radius R from 45 to 135 degrees in the XZ plane (a height field)."""
    a = np.radians([45.0, 90.0, 135.0])
    r = np.array([R, R / W, R])
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)  # (3, 2): x, z


def cylinder_spec():
    xz = _arc_poles()
    poles = [[[x, y, z] for y in (0.0, L)] for x, z in xz]
    return {"type": "nurbs", "degree": [2, 1], "poles": poles,
            "weights": [[1, 1], [W, W], [1, 1]]}


def test_second_derivatives_match_finite_differences():
    spec = cylinder_spec()
    spec["poles"][1][1][2] += 4.0  # not a cylinder any more: every partial is non-trivial
    spec["weights"][1][1] = 0.4
    s = parse_surface(spec)
    u, v, h = np.array([0.37]), np.array([0.61]), 1e-5
    j = s.jet(u, v)
    def p(du, dv):
        return s.points(u + du, v + dv)[0]
    np.testing.assert_allclose(j.su[0], (p(h, 0) - p(-h, 0)) / (2 * h), rtol=1e-6)
    np.testing.assert_allclose(j.suu[0], (p(h, 0) - 2 * p(0, 0) + p(-h, 0)) / h**2, rtol=1e-3, atol=1e-3)
    np.testing.assert_allclose(j.suv[0], (p(h, h) - p(h, -h) - p(-h, h) + p(-h, -h)) / (4 * h * h),
                               rtol=1e-3, atol=1e-3)


def test_registry_names_every_type_and_unknown_keys():
    assert list(SURFACES)[:5] == ["fountas", "choi", "bezier", "bspline", "nurbs"]
    with pytest.raises(ValueError, match=r"^surface.type: expected one of fountas, choi"):
        parse_surface({"type": "cone"})
    with pytest.raises(ValueError, match=r"^surface: unknown key\(s\) for a nurbs surface: wieghts$"):
        parse_surface({**cylinder_spec(), "wieghts": 1})
    with pytest.raises(ValueError, match=r"^surface.flip_normal: expected true or false"):
        parse_surface({"type": "choi", "flip_normal": "yes"})
    from pydantic import TypeAdapter
    settings = TypeAdapter(surface_union()).validate_python(cylinder_spec())
    assert type(settings) is SURFACES["nurbs"]
