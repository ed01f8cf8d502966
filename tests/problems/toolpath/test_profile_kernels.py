"""The planner's compiled passes give the numpy numbers they replace: the drop-cutter's
seeds (``cutters/drop_seeds.py``, against the former KD-tree version kept here as the
reference), a pass's swept bottom (``profile_kernel.window_bottom``), the walk's rate
(``plan/strategies/walk_kernel.py``) and the spacing table's bilinear lookup
(``plan/zoning/lookup_kernel.py``, against ``scipy.ndimage.map_coordinates``)."""

from itertools import chain

import numpy as np
import pytest
from scipy.ndimage import map_coordinates

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.cutters.drop_rim import group_argmax
from evoplan.problems.toolpath.cutters.drop_seeds import bucket_points, drop_seeds
from evoplan.problems.toolpath.cutters.profile_kernel import piece_height, window_bottom
from evoplan.problems.toolpath.cutters.surface_grid import surface_grid
from evoplan.problems.toolpath.geometry.spec import parse_surface
from evoplan.problems.toolpath.plan.strategies.walk_kernel import walk_rate
from evoplan.problems.toolpath.plan.zoning.lookup_kernel import bilinear_nearest
from evoplan.problems.toolpath.plan.zoning.profile import ProfileTable

CUTTERS = [(16, 3, {}), (12, 6, {}), (8, 0, {}), (6.35, 1, {}), (10, 1, {"taper_angle": 10})]


def kd_tree_seeds(cutter, grid, xy):
    """The seeds as drop.py found them before the compiled pass: a KD-tree ball query, the
    numpy profile, the best per query and per quadrant within a tenth of R of it."""
    big = cutter.radius
    lists = grid.tree.query_ball_point(xy, big)
    counts = np.fromiter(map(len, lists), np.int64, len(lists))
    k = len(xy)
    if counts.sum() == 0:
        return np.full((k, 5), -1)
    idx = np.fromiter(chain.from_iterable(lists), np.int64, int(counts.sum()))
    q = np.repeat(np.arange(k), counts)
    d = grid.xy[idx] - xy[q]
    f = grid.z[idx] - cutter.height_jet(0.5 * np.einsum("ij,ij->i", d, d))[0]
    best = group_argmax(q, f, k)
    quad = (d[:, 0] >= 0).astype(np.int64) + 2 * (d[:, 1] >= 0)
    per_quad = np.full((k, 4), -1, np.int64)
    for j in range(4):
        sel = np.flatnonzero(quad == j)
        if len(sel):
            arg = group_argmax(q[sel], f[sel], k)
            per_quad[:, j] = np.where(arg >= 0, sel[np.maximum(arg, 0)], -1)
    best_f = np.where(best >= 0, f[np.maximum(best, 0)], -np.inf)
    quad_f = np.where(per_quad >= 0, f[np.maximum(per_quad, 0)], -np.inf)
    per_quad = np.where(quad_f >= best_f[:, None] - 0.1 * big, per_quad, -1)
    cols = np.concatenate([best[:, None], per_quad], 1)
    return np.where(cols >= 0, idx[np.maximum(cols, 0)], -1)


@pytest.fixture(scope="module")
def fountas():
    return parse_surface("fountas")


@pytest.mark.parametrize("d, r, extra", CUTTERS)
def test_drop_seeds_equal_the_kd_tree_seeds(fountas, d, r, extra):
    cutter = make_cutter(d, r, **extra)
    grid = surface_grid(fountas, float(np.clip(cutter.radius / 10, 0.05, 0.5)))
    lo, hi = grid.xy.min(axis=0) - 2 * cutter.radius, grid.xy.max(axis=0) + 2 * cutter.radius
    xy = np.random.default_rng(int(d * 10 + r)).uniform(lo, hi, (1500, 2))
    xy[:5] = grid.xy[[0, 7, 100, -1, -50]]  # exactly on grid points
    seeds = drop_seeds(cutter, grid, xy)
    assert np.array_equal(seeds, kd_tree_seeds(cutter, grid, xy))
    assert (seeds[:, 0] < 0).any() and (seeds[:, 0] >= 0).mean() > 0.5  # off and on the part
    assert (seeds[:, 1:] >= 0).sum() > len(xy)  # quadrant seeds kept, not only the best


def test_buckets_hold_every_point_once_in_its_cell():
    xy = np.random.default_rng(3).normal(size=(500, 2)) * 10
    b = bucket_points(xy, 1.5)
    assert np.array_equal(np.sort(b.order), np.arange(500))
    cell = np.repeat(np.arange(b.shape[0] * b.shape[1]), np.diff(b.ptr))
    ix = ((xy[b.order, 0] - b.origin[0]) // 1.5).astype(int)
    iy = ((xy[b.order, 1] - b.origin[1]) // 1.5).astype(int)
    assert np.array_equal(cell, np.minimum(iy, b.shape[0] - 1) * b.shape[1] + np.minimum(ix, b.shape[1] - 1))


@pytest.mark.parametrize("d, r, extra", CUTTERS)
def test_piece_height_is_the_numpy_profile(d, r, extra):
    cutter = make_cutter(d, r, **extra)
    rho = np.linspace(0.0, cutter.radius, 401)
    h = np.array([piece_height(x, cutter.kernel_params()) for x in rho])
    assert np.allclose(h, cutter.height(rho), rtol=0, atol=1e-12)
    assert piece_height(cutter.radius * 1.001, cutter.kernel_params()) == np.inf


@pytest.mark.parametrize("reach", [0, 1, 4])
def test_window_bottom_is_the_lowest_tool_bottom_of_the_window(reach):
    cutter = make_cutter(6.35, 1)
    rng = np.random.default_rng(reach)
    m = 60
    tips = np.column_stack([np.linspace(0, 30, m), rng.normal(0, 0.3, m), rng.normal(0, 0.5, m)])
    p = tips[:, :2] + rng.normal(0, 2.0, (m, 2))
    k = np.clip(np.arange(m)[:, None] + np.arange(-reach, reach + 1), 0, m - 1)
    rho = np.linalg.norm(p[:, None, :] - tips[k][:, :, :2], axis=2)
    want = np.min(tips[k][:, :, 2] + cutter.height(rho), axis=1)
    got = window_bottom(p, tips, reach, cutter.kernel_params())
    assert np.allclose(got, want, rtol=0, atol=1e-12)
    assert np.isinf(got).any() == np.isinf(want).any()


def test_walk_rate_moves_along_the_projected_direction(fountas):
    rng = np.random.default_rng(5)
    uv = rng.uniform(0.05, 0.95, (200, 2))
    jet = fountas.jet(uv[:, 0], uv[:, 1], order=1)
    n = np.cross(jet.su, jet.sv)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    d = rng.normal(size=(200, 3))
    rate, unit = walk_rate(jet.su, jet.sv, n, d)
    # unit: d in the tangent plane, made unit; the rate moves the point along it at speed 1
    assert np.allclose(np.linalg.norm(unit, axis=1), 1.0)
    assert np.allclose(np.einsum("ij,ij->i", unit, n), 0.0, atol=1e-12)
    assert np.allclose(rate[:, :1] * jet.su + rate[:, 1:] * jet.sv, unit, atol=1e-9)


def test_bilinear_lookup_is_map_coordinates_bit_for_bit():
    rng = np.random.default_rng(11)
    table = rng.normal(size=(129, 97)) * 3.0 + 5.0
    n = 60_000
    i, j = rng.uniform(-2.0, 131.0, n), rng.uniform(-2.0, 99.0, n)
    i[:2000] = np.round(i[:2000])  # on nodes
    j[2000:4000] = rng.uniform(0.0, 1e-5, 2000) + rng.integers(0, 96, 2000)  # just past a node
    i[4000:6000] = rng.integers(1, 128, 2000) - rng.uniform(0.0, 1e-9, 2000)  # just before one
    i[6000:6003], j[6003:6006] = (np.nan, np.inf, -np.inf), (np.nan, np.inf, -np.inf)
    want = map_coordinates(table, np.stack([i, j]), order=1, mode="nearest")
    got = bilinear_nearest(table, i, j)
    finite = np.isfinite(want)
    assert np.array_equal(got[finite].view(np.uint64), want[finite].view(np.uint64))
    assert np.isnan(got[~finite]).all() and (~finite).sum() == 6  # not finite in: NaN out
    # any shape, the result's that of the indices
    assert np.array_equal(bilinear_nearest(table, i[:600].reshape(20, 30), j[:600].reshape(20, 30)),
                          want[:600].reshape(20, 30))


def test_profile_table_width_equals_its_scipy_reference():
    table = ProfileTable(make_cutter(6.35, 1), 0.254)
    rng = np.random.default_rng(2)
    t_z, beta = rng.uniform(-1.0, 1.0, 20_000), rng.uniform(-1.6, 1.6, 20_000)
    t_z[:500], beta[500:1000] = rng.uniform(-1e-10, 1e-10, 500), 0.0  # near the flat bottom
    assert np.array_equal(table.width(t_z, beta), table.width_numpy(t_z, beta))
