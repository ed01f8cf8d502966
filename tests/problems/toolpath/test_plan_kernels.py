"""The compiled passes of the planner's pass-plane tables and of the 3-axis cusp search give
their numpy references' numbers bit for bit: ``PassGeometry.pass_extent`` and ``seed``
(``plan/seed_kernel.py``), the start and Newton step of ``PassGeometry.locate``, the first
CC points of ``points.sample_sections``, the zone-band membership and runs of
``sections._stretches`` (with ``edge_runs``) and ``scallop_3axis.cusp_heights``
(``criteria/cusp_kernel.py``)."""

import numpy as np
import pytest

from evoplan.problems.toolpath.criteria.scallop_3axis import cusp_heights, cusp_heights_numpy
from evoplan.problems.toolpath.geometry.spec import parse_surface
from evoplan.problems.toolpath.plan.planes import PassGeometry, newton_step_numpy
from evoplan.problems.toolpath.geometry.chord import chord_deviation
from evoplan.problems.toolpath.plan.points import sample_sections, section_points_numpy
from evoplan.problems.toolpath.plan.sections import (_band_inside_numpy, _band_runs_numpy,
                                                      edge_runs, edge_runs_numpy)
from evoplan.problems.toolpath.plan.seed_kernel import (band_inside, band_runs, newton_step,
                                                         section_points, seed_feed, zone_cells)
from evoplan.problems.toolpath.spec import parse_tools


def same_bits(a, b) -> bool:
    a, b = np.ascontiguousarray(a, float), np.ascontiguousarray(b, float)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.fixture(scope="module", params=[0.0, 33.0, 179.5])
def geom(request):
    return PassGeometry(parse_surface("fountas"), request.param)


def queries(geom, q=3000, seed=0):
    rng = np.random.default_rng(seed)
    span = geom.d_max - geom.d_min
    d = rng.uniform(geom.d_min - 0.1 * span, geom.d_max + 0.1 * span, q)
    d[:len(geom.d_grid)] = geom.d_grid  # exactly on the table's nodes
    tau = rng.uniform(-0.2, 1.2, q)
    tau[:65] = np.linspace(0.0, 1.0, 65)
    d[-3:], tau[-6:-3] = np.nan, np.nan
    return d, tau


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # NaN queries cast to int
def test_pass_extent_and_seed_equal_the_numpy_tables_bit_for_bit(geom):
    d, tau = queries(geom)
    for a, b in zip(geom.pass_extent(d), geom.pass_extent_numpy(d)):
        assert same_bits(a, b)
    for a, b in zip(geom.seed(d, tau), geom.seed_numpy(d, tau)):
        assert same_bits(a, b)


def test_band_membership_equals_the_numpy_reference(geom):
    rng = np.random.default_rng(3)
    labels = rng.integers(0, 3, (70, 70))
    P, nt = 40, 90
    d = np.linspace(geom.d_min, geom.d_max, P)
    lo, hi = geom.pass_extent(d)
    s = lo[:, None] + np.linspace(-0.05, 1.05, nt)[None, :] * (hi - lo)[:, None]
    d2 = np.stack([d + off for off in (0.0, 1.3, -2.1, 0.4)])
    lo2, hi2 = geom.pass_extent(d2)
    span = np.where(hi2 > lo2, hi2 - lo2, 1.0)
    for z in range(3):
        ref = _band_inside_numpy(geom, labels, z, s, d2, lo2, span)
        cells = zone_cells(geom.U, geom.V, labels, z)
        every = np.ones_like(cells)
        for maybe in (cells, every):  # the zone's table cells, or every sample seeded
            got = band_inside(geom.d_grid, geom.U, geom.V, labels, z, s, d2, lo2, span, maybe)
            assert got.any() and np.array_equal(got, ref)


def test_zone_cells_skip_only_cells_no_seed_of_which_is_in_the_zone(geom):
    """Every seed of a table cell marked False falls outside zone z (dense seeds), and a
    small zone leaves most cells False."""
    labels = np.zeros((70, 70), np.int64)
    labels[30:36, 40:44] = 1
    cells = zone_cells(geom.U, geom.V, labels, 1)
    assert 0 < cells.sum() < 0.2 * cells.size
    nd, nt = geom.U.shape
    rng = np.random.default_rng(1)
    j0 = rng.integers(0, nd - 1, 20000)
    t0 = rng.integers(0, nt - 1, 20000)
    fj, ft = rng.random(20000), rng.random(20000)
    d = geom.d_grid[j0] + fj * (geom.d_grid[j0 + 1] - geom.d_grid[j0])
    tau = (t0 + ft) / (nt - 1)
    u, v = geom.seed(d, tau)
    i = np.clip((u * 70).astype(np.int64), 0, 69)
    j = np.clip((v * 70).astype(np.int64), 0, 69)
    jj, tt = geom._index(d)[0], np.clip(np.floor(tau * (nt - 1)).astype(int), 0, nt - 2)
    assert not np.any((labels[i, j] == 1) & ~cells[jj, tt])


def test_cusp_heights_equal_the_numpy_search_bit_for_bit():
    rng = np.random.default_rng(5)
    q = 4000
    t_z, b_z = rng.uniform(-0.8, 0.8, q), rng.uniform(-0.8, 0.8, q)
    kappa = rng.normal(0.0, 0.05, q)
    w = rng.uniform(0.0, 12.0, q)
    w[:20], w[20:40], kappa[40:60] = 0.0, 1e3, 10.0  # the first level, none, too concave
    w[-5:] = np.nan
    for cutter in parse_tools(None).cutters:  # flat, torus and ball ends
        got = cusp_heights(cutter, w, t_z, b_z, kappa)
        assert same_bits(got, cusp_heights_numpy(cutter, w, t_z, b_z, kappa)), cutter
        assert np.isinf(got).any() and (got == 0).any()


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # NaN queries cast to int
def test_locate_start_and_newton_step_equal_the_numpy_forms_bit_for_bit(geom):
    d, tau = queries(geom)
    u, v, s = seed_feed(geom.d_grid, geom.U, geom.V, geom.s_lo, geom.s_hi, d, tau)
    lo, hi = geom.pass_extent_numpy(d)
    for a, b in zip((u, v, s), (*geom.seed_numpy(d, tau), lo + tau * (hi - lo))):
        assert same_bits(a, b)
    rng = np.random.default_rng(4)
    q = len(d)
    proj = [rng.normal(size=q) for _ in range(6)]
    proj[2][:5], proj[3][:5], proj[4][:5], proj[5][:5] = 0.0, 0.0, 0.0, 0.0  # det 0
    proj[0][5:8] = np.nan
    uv = (rng.uniform(-0.2, 1.2, q), rng.uniform(-0.2, 1.2, q))
    got = newton_step(d, s, *uv, *proj)
    ref = newton_step_numpy(d, s, *uv, *proj)
    assert all(same_bits(a, b) for a, b in zip(got, ref))


def test_first_section_points_equal_the_numpy_form_bit_for_bit(geom):
    rng = np.random.default_rng(6)
    n = 300
    d = rng.uniform(geom.d_min, geom.d_max, n)
    ta, tb = np.sort(rng.uniform(-0.05, 1.05, (2, n)), axis=0)
    ta[:20], tb[:20] = 0.0, 1.0
    tb[20:30] = ta[20:30]  # empty stretches: one segment
    step = rng.uniform(0.3, 12.0, n)
    got = section_points(geom.d_grid, geom.arc, geom.tau_grid, d, ta, tb, step)
    ref = section_points_numpy(geom, d, ta, tb, step)
    assert np.array_equal(got[0], ref[0]) and np.array_equal(got[2], ref[2])
    assert same_bits(got[1], ref[1])


def test_band_runs_equal_the_numpy_forms_on_a_whole_footprint(geom):
    rng = np.random.default_rng(8)
    P, nt = 60, 120
    d = np.linspace(geom.d_min, geom.d_max, P)
    up, down = rng.uniform(0.0, 3.0, P), rng.uniform(0.0, 3.0, P)
    up[:5], down[-5:] = 0.0, 0.0
    for a, b in zip(edge_runs(geom, d, up, down), edge_runs_numpy(geom, d, up, down)):
        assert same_bits(a, b)
    inside = rng.random((P, nt)) < 0.6
    inside[0], inside[1] = True, False
    tau = np.linspace(0.0, 1.0, nt)
    half = 0.5 / (nt - 1)
    got = band_runs(inside, tau, half, *edge_runs(geom, d, up, down))
    ref = _band_runs_numpy(geom, d, inside, tau, half, up, down)
    assert len(got[0]) > P
    for a, b in zip(got, ref):
        assert a.dtype == b.dtype and (same_bits(a, b) if a.dtype == float else np.array_equal(a, b))


def refined_one_by_one(geom, d, ta, tb, step, tol, max_rounds):
    """The chord refinement of ``sample_sections`` written segment by segment: each
    section's first points, then every segment over the tolerance replaced where it lies by
    m = ceil(sqrt(e / tol)) equal parts in tau, round after round. (tau, err, rounds that
    split) per section."""
    pt_sec, tau, _ = section_points_numpy(geom, d, ta, tb, step)
    out = []
    for k in range(len(d)):
        t = list(tau[pt_sec == k])
        segs = [(t[i], t[i + 1], None) for i in range(len(t) - 1)]
        splits = 0
        for rnd in range(max_rounds + 1):
            nxt, split_any = [], False
            for a, b, e in segs:
                if e is None:
                    # three points at once: one point alone takes BLAS' matrix-vector
                    # product in the surface's jet, whose sums round differently
                    pa, pm, pb = geom.locate(np.full(3, d[k]), np.array([a, 0.5 * (a + b), b]))[2]
                    e = float(chord_deviation(pa[None], pm[None], pb[None])[0])
                    if e > tol and rnd < max_rounds:
                        m = min(int(np.ceil(np.sqrt(e / tol) - 1e-12)), 64)
                        cuts = [a] + [a + (b - a) * j / m for j in range(1, m)] + [b]
                        nxt += [(cuts[j], cuts[j + 1], None) for j in range(m)]
                        split_any = True
                        continue
                nxt.append((a, b, e))
            segs = nxt
            if not split_any:
                break
            splits += 1
        out.append(([s[0] for s in segs] + [segs[-1][1]], [s[2] for s in segs], splits))
    return out


def test_refined_points_stay_in_machining_order_through_every_round(geom):
    """A coarse step and a tight tolerance need several rounds of splits: every section's
    points and chord errors are those of the segment-by-segment refinement, in order (a
    split segment's parts where it lay)."""
    rng = np.random.default_rng(8)
    n = 12
    d = rng.uniform(geom.d_min, geom.d_max, n)
    ta, tb = np.zeros(n), np.ones(n)
    ta[:4], tb[:4] = 0.2, 0.6
    step, tol, rounds = np.full(n, 60.0), 2e-4, 3
    got = sample_sections(geom, d, ta, tb, step, tol, max_rounds=rounds)
    ref = refined_one_by_one(geom, d, ta, tb, step, tol, rounds)
    seg_at = np.cumsum(got.sec_count - 1) - (got.sec_count - 1)
    assert max(r[2] for r in ref) >= 2  # sections split in two rounds or more
    for k, (tau, err, _) in enumerate(ref):
        rows = slice(got.sec_start[k], got.sec_start[k] + got.sec_count[k])
        _, _, p = geom.locate(np.full(len(tau), d[k]), np.array(tau))
        # the same points to round-off: located in other batches, BLAS may round the jet's
        # sums in the last bit (a point alone or at a block's edge)
        assert got.p[rows].shape == p.shape and np.abs(got.p[rows] - p).max() < 1e-12
        assert np.allclose(got.seg_err[seg_at[k]:seg_at[k] + len(err)], err, rtol=1e-9,
                           atol=1e-15)
    assert np.array_equal(got.seg_sec, np.repeat(np.arange(n), got.sec_count - 1))
