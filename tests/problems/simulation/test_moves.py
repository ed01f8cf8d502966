"""The sweep by moves (the default): the entry's slope along a move against finite
differences, and the whole sweep against the dense stamp sweep (which assumes nothing about
the entry along a move) on Fountas' part for a leaning torus, a ball and a flat end."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.clpath import CLPath
from evoplan.problems.toolpath.problem import ToolpathProblem
from evoplan.problems.toolpath.simulation import analytic_grid, design_grid, sweep_path
from evoplan.problems.toolpath.simulation.convex import _at, _move_min
from evoplan.problems.toolpath.simulation.kernel import MISS
from evoplan.problems.toolpath.simulation.moves import _geo, _geo_spans


def _turning_move(end_tip, end_axis):
    """Tips and unit axes of a move from the origin, axis (0.05, -0.03, 1), that shifts and
    turns the cutter."""
    tip = np.array([[0.0, 0.0, 0.0], end_tip])
    ax = np.array([[0.05, -0.03, 1.0], end_axis])
    return tip, ax / np.linalg.norm(ax, axis=1, keepdims=True)


@pytest.mark.parametrize("R, r", [(8.0, 3.0), (6.0, 6.0), (4.0, 0.0)])
def test_entry_slope_is_the_derivative_along_the_move(R, r):
    tip, ax = _turning_move([5.0, 1.0, 0.4], [0.12, 0.02, 1.0])
    rng = np.random.default_rng(3)
    g = np.empty(6)
    checked = 0
    for _ in range(400):
        p = np.r_[rng.uniform(-R, 5 + R, 2), rng.uniform(-1.0, 0.5)]
        d = np.r_[rng.normal(0, 0.2, 2), 1.0]
        d /= np.linalg.norm(d)
        s, e = rng.uniform(0.05, 0.95), 1e-6
        f, slope, _ = _at(s, 0, 1, tip, ax, *p, *d, make_cutter(2 * R, r).kernel_params(), g)
        fp = _at(s + e, 0, 1, tip, ax, *p, *d, make_cutter(2 * R, r).kernel_params(), g)[0]
        fm = _at(s - e, 0, 1, tip, ax, *p, *d, make_cutter(2 * R, r).kernel_params(), g)[0]
        if max(f, fp, fm) > 0.5 * MISS:
            continue
        num = (fp - fm) / (2 * e)
        if abs((fp - f) - (f - fm)) > 1e-3 * e * (1 + abs(num)):
            continue  # a kink (flat bottom to corner, bottom to shank) between the samples
        assert slope == pytest.approx(num, rel=1e-4, abs=1e-5)
        checked += 1
    assert checked > 100


@pytest.mark.parametrize("tool", [6, 8, 1])  # torus D16 r3, ball D12, flat D8
def test_moves_match_the_dense_stamp_sweep(tool):
    pr = ToolpathProblem()
    path, _ = pr.cl_path(dict(tool=tool, stepover=41.729, lead=2.957, tilt=0.027, step=6.338))
    grid = design_grid(pr.surface, 1.0)
    got = sweep_path(path, grid).values
    ref = sweep_path(path, grid, method="stamps", pose_step=0.05, tol=2e-4, n_slots=6).values
    assert (np.isfinite(got) == np.isfinite(ref)).all()
    both = np.isfinite(got)
    # the reference's own error is about its golden-section tolerance (flat rims: its stamps)
    assert np.abs(got - ref)[both].max() < 1e-4


def test_a_turning_axis_bends_the_entry_and_the_bound_allows_for_it():
    # a flat-bottomed torus sweeping a plane while its axis turns by 3 degrees per move: the
    # entry under the flat bottom is then concave along the move, yet the sweep by moves
    # still finds what the dense stamp sweep finds, for every entry within 1 mm of the part
    # (a ray grazing the rim 2.4 mm up may stop at the search's 60 entries, a few um off)
    R, r = 8.0, 3.0
    n = 9
    x = np.linspace(0.0, 48.0, n)
    ang = np.radians(3.0) * np.arange(n) * (-1) ** np.arange(n)
    tips = np.c_[x, np.full(n, 10.0), np.zeros(n)]
    axes = np.c_[np.sin(ang), np.zeros(n), np.cos(ang)]
    path = CLPath(tips, axes, make_cutter(2 * R, r))
    g = analytic_grid(lambda x, y: -0.3 + 0 * x, lambda x, y: (0 * x, 0 * x), (0, 48, 0, 20), 0.25)
    got = sweep_path(path, g).values
    ref = sweep_path(path, g, method="stamps", pose_step=0.02, tol=1e-4, n_slots=6).values
    low = np.isfinite(got) & np.isfinite(ref) & (np.fmin(got, ref) < 1.0)
    assert low.sum() > 0.5 * g.inside.sum()
    assert np.abs(got[low] - ref[low]).max() < 1e-4


@pytest.mark.parametrize("R, r", [(8.0, 3.0), (6.0, 6.0), (4.0, 0.0)])
def test_span_bounds_never_clear_a_stretch_that_cuts(R, r):
    # the geometric bounds of a move cut into spans (what lets the sweep skip a move, or
    # search only part of it, without computing an entry) must keep every pose that enters
    # the ray below T within the stretch [lo, hi] they leave to search
    tip, ax = _turning_move([6.0, 1.0, 0.5], [0.14, 0.03, 1.0])
    rng = np.random.default_rng(5)
    g, e = np.empty(6), np.empty(6)
    s = np.linspace(0.0, 1.0, 2001)
    skipped = narrowed = 0
    for _ in range(300):
        p = np.r_[rng.uniform(-R - 1, 7 + R, 2), rng.uniform(-1.0, 1.0)]
        d = np.r_[rng.normal(0, 0.15, 2), 1.0]
        d /= np.linalg.norm(d)
        f = np.array([_at(si, 0, 1, tip, ax, *p, *d, make_cutter(2 * R, r).kernel_params(), g)[0] for si in s])
        T = f.min() + rng.uniform(-0.5, 0.5)  # a best entry found elsewhere
        whole = np.empty(6)
        _geo(0, 1, tip, ax, *p, *d, whole)
        lo, hi = _geo_spans(0, 1, tip, ax, *p, T, make_cutter(2 * R, r).kernel_params(), whole, e)
        cuts = s[f < T]
        if len(cuts):
            assert lo <= cuts.min() and cuts.max() <= hi
        skipped += lo > hi
        narrowed += lo <= hi and hi - lo < 1.0
    assert skipped > 0 and narrowed > 0  # and they do skip or narrow moves


def test_a_rim_that_only_grazes_the_cell_mid_move_still_cuts():
    # a flat end passes 3.97-3.99 mm beside the cells, so its rim reaches them only over a
    # short stretch in the middle of the move, and a higher pass nearby gives them a first,
    # shallower entry: the spans leave the middle of the move to search, whose ends miss
    R = 4.0
    tips = np.array([[0.0, 0.0, 0.0], [24.0, 0.0, 0.0], [0.0, 5.0, 0.5], [24.0, 5.0, 0.5]])
    path = CLPath(tips, np.tile([0.0, 0.0, 1.0], (4, 1)), make_cutter(2 * R, 0.0), section=np.array([0, 0, 1, 1]))
    g = analytic_grid(lambda x, y: 0 * x, lambda x, y: (0 * x, 0 * x), (11.0, 13.0, 3.96, 4.0), 0.01)
    got = sweep_path(path, g).values
    assert g.inside.sum() >= 200
    assert np.abs(got[g.inside]).max() < 1e-9  # the rim's flat bottom, not the pass 0.5 up


@pytest.mark.parametrize("R, r", [(8.0, 3.0), (6.0, 6.0), (4.0, 0.0)])
def test_a_search_from_a_pose_without_its_ends_finds_the_same_minimum(R, r):
    # the first move a cell searches starts from a pose inside it (the neighbouring cells'
    # minimum, extrapolated) and skips the entries at its ends; where that pose misses
    # the ray it takes them after all. Either way the search finds, within its tolerances,
    # the minimum a dense scan of the move finds (rays entering within 1 mm of the part),
    # and what the search with its ends finds
    tip, ax = _turning_move([6.0, 1.0, 0.5], [0.14, 0.03, 1.0])
    prm = make_cutter(2 * R, r).kernel_params()
    rng = np.random.default_rng(7)
    g, stk, stats = np.empty(6), np.empty((64, 9)), np.zeros(4, np.int64)
    s = np.linspace(0.0, 1.0, 4001)
    tol, bend_tol = 1e-5, 1e-4
    found = fell_back = 0
    for _ in range(300):
        p = np.r_[rng.uniform(-R - 1, 7 + R, 2), rng.uniform(-1.0, 1.0)]
        d = np.r_[rng.normal(0, 0.15, 2), 1.0]
        d /= np.linalg.norm(d)
        f = np.array([_at(si, 0, 1, tip, ax, *p, *d, prm, g)[0] for si in s])
        if f.min() > 1.0:
            continue  # no entry within 1 mm of the part (a ray that only grazes the shank)
        fa, sa, na = _at(0.0, 0, 1, tip, ax, *p, *d, prm, g)
        fb, sb, nb = _at(1.0, 0, 1, tip, ax, *p, *d, prm, g)
        s0 = rng.uniform(0.03, 0.97)
        with_ends = _move_min(0, 1, tip, ax, *p, *d, prm, fa, sa, na, fb, sb, nb,
                              min(fa, fb), tol, bend_tol, 0.05, 30, g, stk, stats, s0, 0.0,
                              1.0)[0]
        before = stats[2]
        no_ends, _, s_low, _ = _move_min(0, 1, tip, ax, *p, *d, prm, 0.0, 0.0, 0.0, 0.0, 0.0,
                                         0.0, np.inf, tol, bend_tol, 0.05, 30, g, stk, stats,
                                         s0, 0.0, 1.0, -1.0, False)
        fell_back += bool(_at(s0, 0, 1, tip, ax, *p, *d, prm, g)[0] >= 0.5 * MISS)
        assert stats[2] > before and 0.0 <= s_low <= 1.0
        # at most the tolerances above the true minimum (<= the scan's), never below the scan
        # by more than its spacing can hide (a rim's V between two samples)
        for got in (with_ends, no_ends):
            assert f.min() - 2e-3 <= got <= f.min() + bend_tol
        assert abs(no_ends - with_ends) <= bend_tol
        found += 1
    assert found > 40 and fell_back > 3, (found, fell_back)
