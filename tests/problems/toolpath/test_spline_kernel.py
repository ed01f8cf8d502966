"""The numba spline kernels agree with scipy's NdBSpline and with the numpy design grid."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import NdBSpline

from evoplan.problems.toolpath.geometry.nurbs import NURBSSurface
from evoplan.problems.toolpath.geometry.spline_kernel import spline_jet
from evoplan.problems.toolpath.simulation import design


def net(seed=0):
    """A rational bicubic-by-quadratic net with a double inner knot, knots on [2, 5] x [-1, 3]."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 60, 7), np.linspace(0, 40, 5), indexing="ij")
    poles = np.stack([x, y, 5 + rng.uniform(-2, 2, x.shape)], axis=-1)
    weights = rng.uniform(0.6, 1.6, x.shape)
    tu = np.r_[[2.0] * 4, 3.0, 3.0, 4.1, [5.0] * 4]
    tv = np.r_[[-1.0] * 3, 0.5, 2.0, [3.0] * 3]
    return poles, weights, tu, tv


def test_spline_jet_equals_ndbspline_to_rounding():
    poles, weights, tu, tv = net()
    h = np.concatenate([poles * weights[..., None], weights[..., None]], axis=2)
    rng = np.random.default_rng(1)
    u = np.r_[2.0, 5.0, 3.0, rng.uniform(2, 5, 500)]  # the ends and a knot included
    v = np.r_[-1.0, 3.0, 0.5, rng.uniform(-1, 3, 500)]
    got = spline_jet(np.ascontiguousarray(h), tu, tv, 3, 2, u, v, 2)
    ref = NdBSpline((tu, tv), h, (3, 2))
    xi = np.column_stack([u, v])
    for i, nu in enumerate([(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]):
        want = ref(xi, nu=nu)
        assert np.abs(got[:, i] - want).max() < 1e-11 * max(1.0, np.abs(want).max()), nu


def test_the_numba_design_grid_of_a_nurbs_equals_the_numpy_one():
    poles, weights, tu, tv = net(2)
    surf = NURBSSurface(poles, weights, (3, 2), tu, tv)
    a = design._design_grid(surf, 0.7, 0.0, None, design._numpy_cells)
    b = design._design_grid(surf, 0.7, 0.0, None, design._spline_cells)
    assert (a.inside == b.inside).all() and a.inside.mean() > 0.9
    assert np.nanmax(np.abs(a.z - b.z)) < 1e-10 and np.abs(a.normal - b.normal).max() < 1e-12
    assert isinstance(b, design.DesignGrid) and design.design_grid(surf, 0.7).z.shape == a.z.shape
