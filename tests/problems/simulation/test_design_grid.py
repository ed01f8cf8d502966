"""The design grid's numba path for polynomial surfaces against its numpy path: the same
cells on the part, z, u, v and normals to 1e-9, the same seed as RegularGridInterpolator,
and the same refusal of a surface that is no graph over XY."""

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from evoplan.problems.toolpath.geometry.bezier import choi_surface
from evoplan.problems.toolpath.geometry.surface import PolynomialSurface, fountas_surface
from evoplan.problems.toolpath.simulation import design
from evoplan.problems.toolpath.simulation.design_poly import bilinear


def _skewed() -> PolynomialSurface:
    """x = 40 u + 12 v^2, y = 30 v + 9 u^2 - 6 u v: a curved footprint, so its bounding box
    holds cells off the part on every side."""
    a = np.zeros((3, 3, 3))
    a[1, 0, 0], a[0, 2, 0] = 40.0, 12.0
    a[0, 1, 1], a[2, 0, 1], a[1, 1, 1] = 30.0, 9.0, -6.0
    a[0, 0, 2], a[2, 0, 2], a[1, 2, 2], a[0, 1, 2] = 5.0, -3.0, 2.0, 1.5
    return PolynomialSurface(a, name="skewed")


def _both(surface, h, margin):
    fast = design.design_grid(surface, h, margin)
    slow = design._design_grid(surface, h, margin, None, design._numpy_cells)
    return fast, slow


@pytest.mark.parametrize("surface, h, margin", [
    (fountas_surface(), 0.5, 1.5),
    (choi_surface(), 0.2, 1.0),
    (_skewed(), 0.25, 0.0),
], ids=["fountas", "choi", "skewed"])
def test_numba_path_equals_numpy_path(surface, h, margin):
    fast, slow = _both(surface, h, margin)
    assert (fast.x0, fast.y0, fast.shape) == (slow.x0, slow.y0, slow.shape)
    on = slow.inside
    assert np.array_equal(fast.inside, on)
    assert on.sum() > 0.5 * on.size and (~on).sum() > 0  # both kinds of cell are compared
    for name in ("z", "u", "v"):
        a, b = getattr(fast, name), getattr(slow, name)
        assert np.isnan(a[~on]).all() and np.isnan(b[~on]).all()
        np.testing.assert_allclose(a[on], b[on], rtol=0, atol=1e-9, err_msg=name)
    np.testing.assert_allclose(fast.normal[on], slow.normal[on], rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(fast.normal[on], axis=-1), 1.0, atol=1e-12)
    # the design point of a cell lies below its centre
    p = surface.points(fast.u[on], fast.v[on])
    X, Y = np.meshgrid(fast.xs, fast.ys)
    np.testing.assert_allclose(p[:, 0], X[on], atol=1e-6)
    np.testing.assert_allclose(p[:, 1], Y[on], atol=1e-6)
    np.testing.assert_allclose(p[:, 2], fast.z[on], atol=1e-9)


def test_flipped_normal_follows_normal_sign():
    up = fountas_surface()
    down = PolynomialSurface(up.coeffs, normal_sign=-1.0)
    with pytest.raises(ValueError, match="not a graph over XY"):
        design.design_grid(down, 1.0)  # the normal points down: refused like a fold
    fast, slow = (design.design_grid(up, 1.0),
                  design._design_grid(up, 1.0, 0.0, None, design._numpy_cells))
    assert (fast.normal[fast.inside][:, 2] > 0).all()
    np.testing.assert_allclose(fast.normal, slow.normal, atol=1e-9)


def test_fold_is_refused_by_both_paths():
    # x = (2u - 1)^2 folds over u = 1/2: two surface points above each (x, y)
    a = np.zeros((3, 2, 3))
    a[0, 0, 0], a[1, 0, 0], a[2, 0, 0] = 1.0, -4.0, 4.0
    a[0, 1, 1] = 10.0
    a[1, 0, 2] = 3.0
    fold = PolynomialSurface(a, normal_sign=1.0)
    for cells in (design._polynomial_cells, design._numpy_cells):
        with pytest.raises(ValueError, match="not a graph over XY"):
            design._design_grid(fold, 0.05, 0.0, None, cells)


def test_seed_is_regular_grid_interpolators_linear_interpolation():
    rng = np.random.default_rng(3)
    tx = np.cumsum(rng.uniform(0.5, 2.0, 12))  # uneven, as RegularGridInterpolator allows
    ty = np.linspace(-3.0, 4.0, 9)
    tab = rng.normal(size=(len(tx), len(ty)))
    x = np.concatenate([rng.uniform(tx[0] - 3, tx[-1] + 3, 400), tx, [tx[-1]] * 9])
    y = np.concatenate([rng.uniform(ty[0] - 3, ty[-1] + 3, 400), ty[[0, -1]].repeat(6), ty])
    want = RegularGridInterpolator((tx, ty), tab, bounds_error=False, fill_value=None)(
        np.stack([x, y], axis=1))
    np.testing.assert_allclose(bilinear(tx, ty, tab, x, y), want, rtol=0, atol=1e-13)
