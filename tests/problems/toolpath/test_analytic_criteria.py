"""The analytic criteria of a PlanBatch: the former evaluator's numbers on the single-zone
5-axis Table 2 sets, finite values, lengths measured on the plan's points, the link / inter-zone split,
Djebali Eq. 4, and the scallop against its closed form on planes."""

import numpy as np
import pytest
from engine_rows import OPTIONS
from engine_rows import genes as _genes
from engine_rows import plans as _plans
from toolpath_analytic import Plane

from evoplan.problems.toolpath.criteria.analytic import analytic_criteria
from evoplan.problems.toolpath.criteria.table import CRITERIA
from evoplan.problems.toolpath.criteria.scallop_3axis import cusp_heights
from evoplan.problems.toolpath.geometry.surface import fountas_surface
from evoplan.problems.toolpath.plan.batch import PlanBatch
from evoplan.problems.toolpath.spec import parse_tools

TABLE2 = np.array([[5, 30.791, 3.379, 0.040, 8.451],   # Fountas Table 2, GA (tool 6: index 5)
                   [5, 41.729, 2.957, 0.027, 6.338]])  # VEGA
#: the criteria of the former analytic evaluator (ToolpathSimulator, retired) for the GA and
#: VEGA sets of TABLE2, as it printed them (runs/reproduce/fountas_table2.md rounds them)
FORMER = {
    "cc_count": (361.0, 289.0),
    "n_passes": (22.0, 17.0),
    "chord_error_mean": (0.005873380077200637, 0.00519827408395001),
    "chord_error_max": (0.009973187532601423, 0.00938000013808605),
    "r_eff": (87.81353208630715, 99.91252479042114),
    "scallop_max": (0.04821426078179325, 0.16688700101052756),
    "scallop_mean": (0.008080240714518227, 0.014686367202611569),
    "gouge_max": (0.0211746611095014, 0.04195339694539531),
    "undercut_max": (0.0, 0.0),
    "machining_error": (0.05240011002354287, 0.1762670011486136),
    "machining_error_mean": (0.018670903468871396, 0.029376186703560386),
    "cutting_length": (2134.6433271585333, 1650.9494277547935),
    "link_length": (115.55070215359292, 115.3880873911905),
    "path_length": (2250.194029312126, 1766.337515145984),
    "machining_time_nominal": (2.250194029312126, 1.7663375151459841),
}

#: the criteria the former evaluator lacked a term of: the gouge of the leaned cutter's pose
#: beside and behind its contact, which the analytic criteria now take as the larger of the
#: two gouges (tests/problems/toolpath/test_heel_gouge.py checks it against the simulation)
POSE_GOUGE = ("gouge_max", "machining_error", "machining_error_mean")


def _random(n, seed, n_tools=9):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.integers(0, n_tools, n), rng.uniform(20, 45, n),
                            rng.uniform(0, 5, n), rng.uniform(0, 2, n), rng.uniform(5, 10, n)])


@pytest.fixture(scope="module")
def fountas():
    surface, tools = fountas_surface(), parse_tools()
    return surface, tools


def test_single_zone_5axis_gives_the_former_evaluators_numbers(fountas):
    """Without the edge overrun (the former evaluator's passes stopped at their last CC
    point) every figure is the former one; with it (the default), only the lengths grow:
    the passes run on past the part's edges, where the cut simulation found the former
    plans' largest scallops (0.303 -> 0.095 mm on the VEGA set, 0.2 mm grid)."""
    surface, tools = fountas
    X = TABLE2
    new = analytic_criteria(_plans(surface, tools, X, edge_overrun=False), surface, tools,
                            _genes(X), **OPTIONS)
    assert set(FORMER) <= set(new)
    for name, old in FORMER.items():
        if name in POSE_GOUGE:  # only raised by the pose gouge (criteria/heel.py)
            assert np.all(new[name] >= np.asarray(old) * (1 - 1e-12)), name
        else:
            np.testing.assert_allclose(new[name], old, rtol=1e-9, atol=0, err_msg=name)
    assert np.all(new["zones"] == 1) and np.all(new["interzone_length"] == 0)
    np.testing.assert_allclose(new["eq4_total"], new["cutting_length"], rtol=1e-15)
    assert np.array_equal(new["n_sections"], new["n_passes"])
    run_on = analytic_criteria(_plans(surface, tools, X), surface, tools, _genes(X), **OPTIONS)
    lengths = ("cutting_length", "link_length", "path_length", "machining_time_nominal", "eq4_total")
    for name in FORMER:
        if name not in lengths:
            np.testing.assert_allclose(run_on[name], new[name], rtol=1e-12, err_msg=name)
    assert np.all(run_on["cutting_length"] > new["cutting_length"])
    assert np.all(run_on["cutting_length"] < 1.1 * new["cutting_length"])


def test_every_criterion_is_finite_where_it_may_be_weighted(fountas):
    surface, tools = fountas
    X = _random(30, seed=3)
    batch = _plans(surface, tools, X)
    for five_axis in (True, False):  # the same CC points judged with a 5- or 3-axis tool
        crit = analytic_criteria(batch, surface, tools, _genes(X, five_axis), **OPTIONS)
        assert tuple(crit) == (  # written out: a table edit must change this line too
            "cc_count", "n_passes", "n_sections", "zones", "chord_error_mean",
            "chord_error_max", "r_eff", "scallop_max", "scallop_mean", "gouge_max",
            "undercut_max", "machining_error", "machining_error_mean", "cutting_length",
            "link_length", "interzone_length", "path_length", "machining_time",
            "machining_time_nominal", "eq4_total", "length_on_part_mm", "length_papers_mm")
        for name, values in crit.items():
            assert values.shape == (30,), name
            assert np.all(np.isfinite(values)) or not CRITERIA[name].weightable, name
            assert np.all(values >= 0) or name == "r_eff", name
        assert np.all(crit["scallop_max"] <= 0.5)  # capped at the allowance
        assert np.all(crit["scallop_max"] + crit["gouge_max"] > 0)  # no gap is exact
    flat = X[:, 0] < 6  # flat-end and toroidal tools at zero lead and tilt: a flat bottom
    crit = analytic_criteria(batch, surface, tools, _genes(X) | {"lead": 0 * X[:, 2],
                             "tilt": 0 * X[:, 3]}, **OPTIONS)
    assert np.all(np.isinf(crit["r_eff"][flat])) and np.all(np.isfinite(crit["r_eff"][~flat]))


def test_cutting_length_is_the_length_of_the_sections_polylines(fountas):
    surface, tools = fountas
    X = _random(6, seed=11)
    batch = _plans(surface, tools, X)
    crit = analytic_criteria(batch, surface, tools, _genes(X), **OPTIONS)
    expected, links = np.zeros(6), np.zeros(6)
    for s in range(len(batch.sec_ind)):
        pts = batch.p[batch.sec_start[s]:batch.sec_start[s] + batch.sec_count[s]]
        expected[batch.sec_ind[s]] += np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()
        if s + 1 < len(batch.sec_ind) and batch.sec_ind[s + 1] == batch.sec_ind[s]:
            links[batch.sec_ind[s]] += np.linalg.norm(batch.p[batch.sec_start[s + 1]] - pts[-1])
    np.testing.assert_allclose(crit["cutting_length"], expected, rtol=1e-12)
    np.testing.assert_allclose(crit["link_length"], links, rtol=1e-12)
    np.testing.assert_allclose(crit["machining_time_nominal"],
                               (crit["cutting_length"] + crit["link_length"]) / 1000.0, rtol=1e-12)


def _hand_batch(sections, spacing):
    """PlanBatch on the plane z = 0 over [0, 100] x [0, 60] from sections given as
    (individual, zone, pass, y, xs in travel order, side)."""
    secs, pts = [], []
    for ind, zone, k, y, xs, side in sections:
        secs.append((ind, zone, k, y, xs[-1] < xs[0], side, len(pts), len(xs)))
        pts += [(len(secs) - 1, x, y) for x in xs]
    si, sz, sk, sy, rev, side, start, count = (np.array(c) for c in zip(*secs))
    pt_sec, x, y = (np.array(c) for c in zip(*pts))
    p = np.column_stack([x, y, 0 * x])
    last = np.r_[pt_sec[1:] != pt_sec[:-1], True]
    seg = np.flatnonzero(~last)
    n = int(si.max()) + 1
    return PlanBatch(
        n=n, zones=np.array([sz[si == i].max() + 1 for i in range(n)]), sec_ind=si, sec_zone=sz,
        sec_pass=sk, sec_d=sy.astype(float), sec_alpha=np.zeros(len(si)), sec_reverse=rev,
        sec_spacing=np.full(len(si), spacing), sec_side=side, sec_start=start, sec_count=count,
        pt_sec=pt_sec, u=x / 100.0, v=y / 60.0, p=p, normal=np.tile([0.0, 0, 1], (len(x), 1)),
        tangent=np.column_stack([np.where(rev[pt_sec], -1.0, 1.0), 0 * x, 0 * x]),
        axis=np.tile([0.0, 0, 1], (len(x), 1)), tip=p, chord=np.zeros(len(x)),
        on_part=np.ones(len(x), bool), seg_sec=pt_sec[seg], seg_err=np.zeros(len(seg)),
        seg_len=np.linalg.norm(p[seg + 1] - p[seg], axis=1))


def test_links_inside_a_zone_and_moves_between_zones():
    sections = [  # individual 0: two zones of two passes; individual 1: one zone
        (0, 0, 0, 10, [0, 20, 40], 1), (0, 0, 1, 14, [40, 20, 0], -1),
        (0, 1, 0, 10, [60, 80, 100], 1), (0, 1, 1, 14, [100, 80, 60], -1),
        (1, 0, 0, 10, [0, 50, 100], 1), (1, 0, 1, 14, [100, 50, 0], -1)]
    tools = parse_tools([{"diameter": 16, "corner_radius": 8}])
    genes = {"tool": np.zeros(2, int), "lead": np.zeros(2), "tilt": np.zeros(2)}
    crit = analytic_criteria(_hand_batch(sections, 4.0), Plane(), tools, genes, **OPTIONS)
    np.testing.assert_allclose(crit["cutting_length"], [160.0, 200.0])
    np.testing.assert_allclose(crit["link_length"], [8.0, 4.0])
    np.testing.assert_allclose(crit["interzone_length"], [np.hypot(60.0, 4.0), 0.0])
    np.testing.assert_allclose(crit["path_length"], [168.0 + np.hypot(60.0, 4.0), 204.0])
    np.testing.assert_allclose(crit["eq4_total"], [160.0 + 40.0, 200.0])  # Djebali Eq. 4
    assert np.array_equal(crit["zones"], [2, 1]) and np.array_equal(crit["n_passes"], [4, 2])
    assert np.array_equal(crit["cc_count"], [12, 6])
    h = 8.0 - np.sqrt(64.0 - 2.0 ** 2)  # ball R 8, w 4 on a plane
    np.testing.assert_allclose(crit["scallop_max"], h, rtol=1e-3)
    np.testing.assert_allclose(crit["scallop_mean"], h, rtol=1e-3)
    assert np.all(crit["gouge_max"] == 0)


@pytest.mark.parametrize("slope", [0.0, 0.5])
def test_ball_scallop_on_a_plane_is_the_closed_form(slope):
    """Ball R 6, XY step-over delta across a plane rising along the cross-feed: the CC points
    are delta / cos(atan slope) apart on the surface, h = R - sqrt(R^2 - (w/2)^2), in 5-axis
    (profile tables) and in 3-axis (circle model, exact for a ball)."""
    tools = parse_tools([{"diameter": 12, "corner_radius": 6}])
    surface = Plane(b=slope)
    X = np.array([[0, 20.0, 0.0, 0.0, 8.0], [0, 35.0, 0.0, 0.0, 8.0]])
    w = X[:, 1] / 100 * 12 * np.sqrt(1 + slope ** 2)
    h = 6.0 - np.sqrt(36.0 - (w / 2) ** 2)
    for machine, rtol in (("5axis", 1e-3), ("3axis", 1e-12)):
        batch = _plans(surface, tools, X, machine)
        crit = analytic_criteria(batch, surface, tools, _genes(X, machine == "5axis"), **OPTIONS)
        np.testing.assert_allclose(crit["scallop_max"], h, rtol=rtol)
        np.testing.assert_allclose(crit["machining_error"], h, rtol=rtol)
        assert np.all(crit["gouge_max"] == 0) and np.all(crit["r_eff"] == 6.0)


def test_a_zone_of_one_plane_leaves_no_modelled_scallop():
    tools = parse_tools([{"diameter": 12, "corner_radius": 6}])
    batch = _hand_batch([(0, 0, 0, 10, [0, 50, 100], 0)], 4.0)
    crit = analytic_criteria(batch, Plane(), tools, {"tool": np.zeros(1, int)}, **OPTIONS)
    assert crit["scallop_max"][0] == 0 and crit["link_length"][0] == 0
    assert crit["n_passes"][0] == 1 and crit["cutting_length"][0] == 100.0


def test_3axis_torus_on_a_plane_is_the_corner_arc_closed_form():
    """Vertical torus D12 r2 on a horizontal plane: the flat bottom (half-width R0 = 4) covers
    a gap up to 8 mm; beyond, the corner arcs meet at h = r - sqrt(r^2 - (w/2 - R0)^2). The
    circle of R_eff (infinite here) would say 0 for both."""
    tools = parse_tools([{"diameter": 12, "corner_radius": 2}])
    X = np.array([[0, 50.0, 0.0, 0.0, 8.0], [0, 80.0, 0.0, 0.0, 8.0]])  # w 6 and 9.6 mm
    surface = Plane(0.0, 96.0, 0.0, 96.0)  # a whole number of passes: no shorter last one
    crit = analytic_criteria(_plans(surface, tools, X, "3axis"), surface, tools,
                             _genes(X, False), **OPTIONS)
    h = 2.0 - np.sqrt(4.0 - (9.6 / 2 - 4.0) ** 2)
    assert crit["scallop_max"][0] == 0.0
    np.testing.assert_allclose(crit["scallop_max"][1], h, rtol=5e-3)
    assert np.all(crit["gouge_max"] == 0) and np.all(np.isinf(crit["r_eff"]))


@pytest.mark.parametrize("tool", [2, 5])  # flat-end D16, toroidal D12 r2
def test_3axis_cusp_inverts_the_planners_spacing_model(tool):
    """The cusp height read back at the width the profile spans at h (both sides, flat
    section, ``Cutter.swept_side_width``) is h."""
    cutter = parse_tools().cutter(tool)
    rng = np.random.default_rng(tool)
    t_z, beta, h = rng.uniform(0, 0.8, 300), rng.uniform(-1, 1, 300), np.geomspace(0.002, 0.5, 300)
    w = cutter.swept_side_width(h, t_z, beta) + cutter.swept_side_width(h, t_z, -beta)
    got = cusp_heights(cutter, w, t_z, np.sin(beta) * np.sqrt(1 - t_z ** 2), np.zeros(300))
    rel = np.abs(got / h - 1)
    assert np.percentile(rel, 95) < 0.01 and rel.max() < 0.05
