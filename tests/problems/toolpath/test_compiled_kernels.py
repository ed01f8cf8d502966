"""The compiled passes of the evaluation's hot spots give the numpy reference's numbers bit
for bit: ``geometry.rows.interp_rows`` (per-query bisection) and the torus family's
``cc_to_tip`` (``cutters/shapes.py``)."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters.base import Cutter
from evoplan.problems.toolpath.geometry.rows import interp_rows, interp_rows_numpy
from evoplan.problems.toolpath.spec import parse_tools


def same_bits(a, b) -> bool:
    a, b = np.ascontiguousarray(a, float), np.ascontiguousarray(b, float)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.mark.parametrize("m", [2, 3, 5, 17, 64])
@pytest.mark.parametrize("shared", [False, True])
def test_interp_rows_equals_the_numpy_bisection_bit_for_bit(m, shared):
    rng = np.random.default_rng(m)
    k, q = 30, 400
    xp = np.sort(rng.normal(size=(k, m)), axis=1)
    xp[:, 1] = np.where(rng.random(k) < 0.2, xp[:, 0], xp[:, 1])  # repeated abscissae
    fp = rng.normal(size=m) if shared else rng.normal(size=(k, m))
    x = 2.0 * rng.normal(size=q)  # below, inside and above the tables
    x[rng.random(q) < 0.05] = np.nan
    x[:k] = xp[:, 0]  # exactly on a table's first abscissa
    rows = rng.integers(0, k, q)
    rows[:k] = np.arange(k)
    assert same_bits(interp_rows(xp, fp, x, rows), interp_rows_numpy(xp, fp, x, rows))
    # a query alone gives the number it gives in its batch (finite queries)
    i = np.flatnonzero(np.isfinite(x))[:20]
    alone = [interp_rows(xp, fp, x[j:j + 1], rows[j:j + 1])[0] for j in i]
    assert same_bits(alone, interp_rows(xp, fp, x, rows)[i])


def test_interp_rows_is_linear_interpolation():
    xp = np.array([[0.0, 1.0, 3.0], [0.0, 2.0, 4.0]])
    fp = np.array([[0.0, 10.0, 30.0], [5.0, 5.0, 9.0]])
    out = interp_rows(xp, fp, np.array([0.5, 2.0, -1.0, 3.0, 9.0]), np.array([0, 0, 0, 1, 1]))
    np.testing.assert_allclose(out, [5.0, 20.0, 0.0, 7.0, 9.0], rtol=0, atol=1e-15)


@pytest.mark.parametrize("axis", ["per point", "vertical", "shared tilted"])
def test_torus_family_cc_to_tip_equals_the_numpy_support_point_bit_for_bit(axis):
    rng = np.random.default_rng(7)
    k = 5000
    cc = 50.0 * rng.normal(size=(k, 3))
    n = rng.normal(size=(k, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    a = {"per point": rng.normal(size=(k, 3)), "vertical": (0.0, 0.0, 1.0),
         "shared tilted": np.array([0.1, 0.2, 0.97])}[axis]
    if axis == "per point":
        a[:50], a[50:100] = -n[:50], n[50:100]  # d = -a and d = a: no rim direction (e = 0)
    for cutter in parse_tools(None).cutters:  # flat, torus and ball ends
        assert same_bits(cutter.cc_to_tip(cc, n, a), Cutter.cc_to_tip(cutter, cc, n, a)), cutter


def test_ball_tip_lies_a_radius_below_the_centre_on_the_normal():
    ball = next(c for c in parse_tools(None).cutters if c.kind == "ball")
    cc, n = np.array([[1.0, 2.0, 3.0]]), np.array([[0.0, 0.6, 0.8]])
    tip = ball.cc_to_tip(cc, n, np.array([[0.0, 0.0, 1.0]]))
    np.testing.assert_allclose(tip, cc + ball.radius * n - [[0, 0, ball.radius]], atol=1e-12)
