"""The one planner: decisions -> zones -> passes -> CC points -> orientation -> CL points."""

from __future__ import annotations

import numpy as np
import pytest

from evoplan.problems.toolpath.geometry.spec import parse_surface
from evoplan.problems.toolpath.plan.planner import Planner
from evoplan.problems.toolpath.plan.zones import ZoningSpec
from evoplan.problems.toolpath.simulation import design_grid, residual_metrics, sweep_path
from evoplan.problems.toolpath.spec import parse_tools

TORUS = [{"id": 1, "type": "toroidal", "diameter": 6.35, "corner_radius": 1.0}]
H_C = 0.254


def _two_planes():
    """z = 0.3 x + 0.6 |y - 50| over [0, 50] x [0, 100]: two planes meeting in a valley
    along y = 50, steepest slopes at 116.6 deg (y < 50) and 63.4 deg (y > 50)."""
    x, y = np.linspace(0, 50, 3), np.array([0.0, 50.0, 100.0])
    X, Y = np.meshgrid(x, y, indexing="ij")
    net = np.stack([X, Y, 0.3 * X + 0.6 * np.abs(Y - 50)], axis=-1)
    return parse_surface({"type": "bspline", "degree": [1, 1], "poles": net.tolist()})


def _one(**genes):
    return {k: np.atleast_1d(np.asarray(v)) for k, v in genes.items()}


def test_two_plane_surface_gives_two_zones_each_fed_along_its_slope():
    surface = _two_planes()
    planner = Planner(surface, parse_tools(TORUS), machine="3axis", spacing="scallop", h_c=H_C,
                      feed_angle=None, zoning=ZoningSpec("amas", mesh=(20, 20), merge=None))
    batch = planner.plan(_one(tool=0, step=2.0, k_lz=0.15), place=False)
    assert batch.zones.tolist() == [2]
    labels = planner.layouts.get(0.15, 0).labels
    assert len(np.unique(labels[:, :10])) == 1 and len(np.unique(labels[:, 10:])) == 1
    assert labels[0, 0] != labels[0, -1]  # the zones are the two planes (v < 1/2, v > 1/2)
    slope_dir = {int(labels[0, 0]): 180 - 63.43, int(labels[0, -1]): 63.43}
    for z, expected in slope_dir.items():
        got = np.degrees(batch.sec_alpha[batch.sec_zone == z])
        assert np.allclose(got, got[0]) and abs(got[0] - expected) < 2.0, (z, got[0])


def test_single_zone_points_follow_the_max_step_and_the_chord_tolerance():
    surface = parse_surface("fountas")
    planner = Planner(surface, parse_tools(None), machine="5axis", tolerance=0.01)
    rng = np.random.default_rng(3)
    n = 6
    genes = dict(tool=rng.integers(0, 9, n), stepover=rng.uniform(20, 45, n),
                 lead=rng.uniform(0, 5, n), tilt=rng.uniform(0, 2, n), step=rng.uniform(5, 10, n))
    b = planner.plan(genes)
    assert b.zones.tolist() == [1] * n
    assert np.all(b.seg_len <= genes["step"][b.seg_ind] + 1e-9)
    assert np.all(b.seg_err <= 0.01 + 1e-12)
    # zig-zag: consecutive passes of one plan travel in opposite directions along the feed
    for i in range(n):
        s = np.flatnonzero(b.sec_ind == i)
        assert np.array_equal(b.sec_reverse[s], np.arange(len(s)) % 2 == 1)
        assert np.all(np.diff(b.sec_d[s]) > 0)
        t = b.tangent[b.sec_start[s]]
        assert np.all(np.sign(t[:, 0]) == np.where(b.sec_reverse[s], -1, 1))


def test_5axis_axis_has_the_lead_and_tilt_angles():
    surface = parse_surface("fountas")
    planner = Planner(surface, parse_tools(None), machine="5axis")
    b = planner.plan(_one(tool=5, stepover=30.0, lead=4.0, tilt=1.5, step=8.0))
    a, n, t = b.axis, b.normal, b.tangent
    lead = np.degrees(np.arcsin(np.sum(a * t, axis=1)))
    tilt = np.degrees(np.arctan2(np.sum(a * np.cross(n, t), axis=1), np.sum(a * n, axis=1)))
    assert np.allclose(lead, 4.0) and np.allclose(tilt, 1.5)
    # the tool touches the surface at the CC point: the tip is the tangent placement; past
    # the part's edge the run-on rows' tips are lifted along the normal off their nominal
    # point (the osculating parabola where the surface is concave along the travel)
    cutter = parse_tools(None).cutter(5)
    on = b.on_part
    assert np.allclose(b.tip[on], cutter.cc_to_tip(b.p[on], n[on], a[on]))
    lift = b.tip[~on] - cutter.cc_to_tip(b.p[~on], n[~on], a[~on])
    along = np.einsum("ij,ij->i", lift, n[~on])
    assert (~on).any() and np.allclose(lift, along[:, None] * n[~on]) and np.all(along >= 0)
    assert along.max() > 0  # Fountas' part is concave along the feed at some pass ends


def test_claimed_cut_length_is_the_length_of_the_sections_of_the_cl_path():
    planner = Planner(parse_surface("choi"), parse_tools(TORUS), machine="3axis",
                      spacing="stepover", feed_angle=None,
                      zoning=ZoningSpec("kmeans", mesh=(24, 24)))
    genes = _one(tool=0, stepover=60.0, step=1.5, zones=3)
    b = planner.plan(genes, place=False)
    path = planner.cl_path(genes)
    cc, sec = path.info["cc"], path.section
    same = sec[1:] == sec[:-1]
    cut = float(np.linalg.norm(np.diff(cc, axis=0), axis=1)[same].sum())
    # the CL chord tolerance inserts points on the same section curves: the length grows
    # only by the curve-versus-chord difference (second order)
    assert cut == pytest.approx(float(b.seg_len.sum()), rel=2e-3)
    assert len(np.unique(path.zone)) == b.zones[0] >= 2


@pytest.fixture(scope="module")
def choi_grid():
    return design_grid(parse_surface("choi"), 0.5)


@pytest.mark.parametrize("method, genes", [("single", {}), ("kmeans", {"zones": 2})])
def test_scallop_spacing_plans_meet_h_c_in_the_cut_simulation(choi_grid, method, genes):
    """The physical claim: a plan spaced for h_c leaves p99 under h_c and its maximum within
    10 % of it (the bands of zoned planes reach across zone borders, the passes run on past
    the part's edges), cuts every cell and does not gouge (drop-cutter placement, CL chord
    tolerance 0.01 mm)."""
    planner = Planner(parse_surface("choi"), parse_tools(TORUS), machine="3axis", spacing="scallop", h_c=H_C,
                      feed_angle=None, zoning=ZoningSpec(method, mesh=(40, 40)))
    path = planner.cl_path({"tool": [0], "step": [1.0], **{k: [v] for k, v in genes.items()}})
    m = residual_metrics(choi_grid, sweep_path(path, choi_grid).values, allowance=0.5)
    assert m["scallop_p99_mm"] < H_C
    assert m["scallop_max_mm"] < 1.1 * H_C  # zone borders and part edges included
    assert m["uncut_fraction"] == 0.0
    assert m["gouge_max_mm"] < 0.01


def test_missing_gene_and_bad_settings_are_one_line_errors():
    planner = Planner(parse_surface("fountas"), parse_tools(None))
    assert planner.gene_names == ("tool", "stepover", "lead", "tilt", "step")
    with pytest.raises(ValueError, match="genes: missing lead, tilt"):
        planner.plan(_one(tool=0, stepover=30.0, step=5.0))
    with pytest.raises(ValueError, match="^spacing: "):
        Planner(parse_surface("fountas"), parse_tools(None), spacing="adaptive")
    with pytest.raises(ValueError, match="^machine: "):
        Planner(parse_surface("fountas"), parse_tools(None), machine="4axis")
    three = Planner(parse_surface("choi"), parse_tools(TORUS), machine="3axis",
                    spacing="scallop", h_c=H_C, zoning=ZoningSpec("kmeans"))
    assert three.gene_names == ("tool", "step", "zones")


def test_edge_overrun_runs_sections_past_the_edge_without_cc_points():
    planner = Planner(parse_surface("choi"), parse_tools(TORUS), machine="3axis",
                      spacing="stepover", feed_angle=0.0)
    b = planner.plan(_one(tool=0, stepover=50.0, step=2.0))
    off = ~b.on_part
    assert off.any()
    # the extra points lie at the ends of the sections, beyond the footprint's edge in XY
    j = np.arange(len(b.u)) - b.sec_start[b.pt_sec]
    from_end = b.sec_count[b.pt_sec] - 1 - j
    assert np.all((j[off] < 3) | (from_end[off] < 3))
    # the tool's centre reaches the XY of every section's end CC points (a vertical tool
    # tangent on a surface rising towards the edge stops short of it)
    assert np.all(np.isfinite(b.tip))
    for s in range(len(b.sec_start)):
        idx = np.arange(b.sec_start[s], b.sec_start[s] + b.sec_count[s])
        cc_x = b.p[idx[b.on_part[idx]], 0]
        assert b.tip[idx, 0].min() <= cc_x.min() + 1e-6
        assert b.tip[idx, 0].max() >= cc_x.max() - 1e-6
    # the plan's lengths count the overrun moves: the CC polyline of every section
    seg = np.linalg.norm(np.diff(b.p, axis=0), axis=1)[b.pt_sec[1:] == b.pt_sec[:-1]]
    assert float(seg.sum()) == pytest.approx(float(b.seg_len.sum()), rel=1e-9)


def test_a_plan_does_not_depend_on_the_other_plans_of_its_batch():
    """Backends split a population differently (serial, processes, Dask): every plan and
    every criterion must be the same bit for bit, whatever else is in the batch."""
    from evoplan.problems.toolpath.criteria.analytic import analytic_criteria
    from evoplan.problems.toolpath.geometry.rows import interp_rows

    surface, tools = parse_surface("fountas"), parse_tools(None)
    planner = Planner(surface, tools, machine="5axis")
    rng = np.random.default_rng(5)
    n = 8
    genes = dict(tool=rng.integers(0, 9, n), stepover=rng.uniform(20, 45, n),
                 lead=rng.uniform(0, 5, n), tilt=rng.uniform(0, 2, n), step=rng.uniform(5, 10, n))
    kw = dict(allowance=0.5, feed_rate=1000.0, delta_l=40.0)
    whole = planner.plan(genes)
    crit = analytic_criteria(whole, surface, tools, genes, **kw)
    for i in (0, 3, 7):
        one = {k: v[i:i + 1] for k, v in genes.items()}
        alone = planner.plan(one)
        idx = whole.points_of(i)
        assert np.array_equal(alone.p, whole.p[idx]) and np.array_equal(alone.tip, whole.tip[idx])
        crit_one = analytic_criteria(alone, surface, tools, one, **kw)
        for name, values in crit.items():
            assert np.array_equal(crit_one[name], values[i:i + 1], equal_nan=True), name
    # the row interpolation is np.interp, row by row
    xp = np.sort(rng.uniform(0, 10, (50, 7)), axis=1)
    fp = rng.normal(size=(50, 7))
    x = rng.uniform(-1, 11, 50)
    expected = [np.interp(x[i], xp[i], fp[i]) for i in range(50)]
    assert np.allclose(interp_rows(xp, fp, x), expected, rtol=0, atol=1e-12)


def test_a_pickled_planner_is_small_and_plans_the_same():
    """The processes backend sends the problem to its workers: the zone layouts' memo and
    samples stay behind and are rebuilt, with the same numbers."""
    import pickle

    planner = Planner(parse_surface("choi"), parse_tools(TORUS), machine="3axis",
                      spacing="scallop", h_c=H_C, feed_angle=None,
                      zoning=ZoningSpec("kmeans", mesh=(12, 12)))
    genes = _one(tool=0, step=1.0, zones=2)
    before = planner.plan(genes, place=False)
    data = pickle.dumps(planner)
    assert len(data) < 2_000_000
    after = pickle.loads(data).plan(genes, place=False)
    assert np.array_equal(before.p, after.p) and np.array_equal(before.seg_len, after.seg_len)


def test_row_interpolation_with_a_row_per_query_and_a_shared_table_matches_np_interp():
    """Both forms the plan uses: queries naming their table (``rows``), values shared by
    every table (1-D ``fp``), queries at the tables' nodes and outside them; and ``ranges``
    numbering the rows of blocks laid end to end."""
    from evoplan.problems.toolpath.geometry.rows import interp_rows, ranges

    rng = np.random.default_rng(11)
    xp = np.sort(rng.uniform(0, 10, (6, 9)), axis=1)
    fp = np.linspace(0.0, 1.0, 9) ** 2
    rows = rng.integers(0, 6, 80)
    x = np.r_[rng.uniform(-1, 11, 60), xp[rows[60:], rng.integers(0, 9, 20)]]
    expected = [np.interp(x[i], xp[r], fp) for i, r in enumerate(rows)]
    assert np.allclose(interp_rows(xp, fp, x, rows), expected, rtol=0, atol=1e-12)
    owner, pos = ranges(np.array([2, 0, 3]))
    assert owner.tolist() == [0, 0, 2, 2, 2] and pos.tolist() == [0, 1, 0, 1, 2]
