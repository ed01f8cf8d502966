"""Surface.footprint: the unit square by default; trimmed loops with a hole (even-odd rule)."""

import numpy as np
import pytest

from evoplan.problems.toolpath.geometry.footprint import UNIT_SQUARE, Footprint
from evoplan.problems.toolpath.geometry.spec import parse_surface


def test_every_shipped_surface_has_the_whole_square():
    for name in ("fountas", "choi"):
        fp = parse_surface(name).footprint
        assert fp is UNIT_SQUARE and fp.area() == 1.0
        assert fp.contains([0, 0.5, 1, 1.01, -0.01], [0, 0.5, 1, 0.5, 0.5]).tolist() == \
            [True, True, True, False, False]


def test_a_hole_is_not_material():
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    hole = np.column_stack([0.5 + 0.2 * np.cos(t), 0.5 + 0.2 * np.sin(t)])
    outer = [[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.5, 0.75], [0.1, 0.9]]  # non-convex top
    fp = Footprint([outer, hole])
    rng = np.random.default_rng(3)
    u, v = rng.random(20000), rng.random(20000)
    inside = fp.contains(u, v)
    in_hole = np.hypot(u - 0.5, v - 0.5) < 0.19
    assert not inside[in_hole].any()
    assert inside[(np.hypot(u - 0.5, v - 0.5) > 0.21) & (u > 0.12) & (u < 0.88)
                  & (v > 0.12) & (v < 0.5)].all()
    assert not fp.contains([0.5], [0.8])[0]  # above the notch of the outer loop
    # the sampled fraction agrees with the shoelace area of outer minus hole
    assert abs(inside.mean() - fp.area()) < 0.01
    with pytest.raises(ValueError, match="footprint loop 1"):
        Footprint([outer, [[0, 0], [1, 1]]])
