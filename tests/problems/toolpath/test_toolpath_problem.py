"""ToolpathProblem: pymoo interface, objective, plain-data input and its errors."""

import json
import pickle

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from pymoo.core.variable import Choice, Real

from evoplan.problems.toolpath import ToolpathProblem, choi_surface
from evoplan.problems.toolpath.geometry.bezier import choi_poles

GA = dict(tool=6, stepover=30.791, lead=3.379, tilt=0.040, step=8.451)
VEGA = dict(tool=6, stepover=41.729, lead=2.957, tilt=0.027, step=6.338)
FIXED = {"machining_error": [0.0, 1.0], "cc_count": [0.0, 2000.0]}  # skip the design sample


def test_variables_bounds_and_tool_numbering(fountas_problem):
    p = fountas_problem
    assert p.n_var == 5 and p.n_obj == 1 and p.vars is p.variables  # pymoo mixed-variable form
    np.testing.assert_array_equal(p.xl, [0, 20, 0, 0, 5])
    np.testing.assert_array_equal(p.xu, [8, 45, 5, 2, 10])
    assert list(p.variables) == ["tool", "stepover", "lead", "tilt", "step"]
    assert isinstance(p.variables["tool"], Choice) and p.variables["tool"].options == list(range(1, 10))
    assert all(isinstance(p.variables[k], Real) for k in ("stepover", "lead", "tilt", "step"))
    assert p.variables["step"].bounds == (5.0, 10.0)
    tool6 = p.tool_db.tools[p.tool_db.index_of(6)]
    assert (tool6.type, tool6.diameter, tool6.corner_radius) == ("toroidal", 16.0, 3.0)  # phi16 Rc3


def test_vega_parameters_give_the_papers_289_cc_points(fountas_problem):
    # 103.2 / 6.677 mm -> 17 planes; ~96.5 mm / 6.338 -> 16 segments each, chord errors
    # below the tolerance at that step (no refinement): 17 x 17 (Fountas: 289)
    c = fountas_problem.evaluate_params(VEGA)
    assert c["n_passes"] == 17 and c["cc_count"] == 289
    g = fountas_problem.evaluate_params(GA)
    assert g["cc_count"] > c["cc_count"] and g["chord_error_mean"] > c["chord_error_mean"]
    assert c["chord_error_max"] <= 0.01 and g["chord_error_max"] <= 0.01


def test_objective_is_eq9_of_the_fixed_normalized_criteria(fountas_problem):
    p = fountas_problem
    X = np.vstack([p.row(GA), p.row(VEGA)])
    crit = p.criteria(X)
    (elo, ehi), (clo, chi) = p.norm_bounds["machining_error"], p.norm_bounds["cc_count"]
    by_hand = (0.5 * (crit["machining_error"] - elo) / (ehi - elo)
               + 0.5 * (crit["cc_count"] - clo) / (chi - clo))
    np.testing.assert_allclose(p.evaluate(X)[:, 0], by_hand, rtol=1e-12)
    np.testing.assert_allclose(crit["objective"], by_hand, rtol=1e-12)


def test_normalization_is_fixed_not_population_dependent(fountas_problem):
    p = fountas_problem
    rng = np.random.default_rng(5)
    X = p.xl + rng.random((30, 5)) * (p.xu - p.xl)
    X[:, 0] = rng.integers(0, 9, 30)
    before = dict(p.norm_bounds)
    batch = p.evaluate(X)[:, 0]
    alone = np.array([p.evaluate(X[i:i + 1])[0, 0] for i in range(0, 30, 7)])
    np.testing.assert_allclose(batch[::7], alone, rtol=1e-12)
    assert p.norm_bounds == before
    assert ToolpathProblem().norm_bounds == before  # the seeded design is reproducible


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 8), st.floats(20, 45), st.floats(0, 5), st.floats(0, 2),
                          st.floats(5, 10)), min_size=1, max_size=12))
def test_objective_and_criteria_are_finite_over_the_whole_box(fountas_problem, rows):
    X = np.array(rows, float)
    F = fountas_problem.evaluate(X)
    assert F.shape == (len(rows), 1) and np.all(np.isfinite(F))
    crit = fountas_problem.criteria(X)
    for k, v in crit.items():
        if k != "r_eff":
            assert np.all(np.isfinite(v)), k
    assert not np.any(np.isnan(crit["r_eff"])) and np.all(crit["r_eff"] >= 0)  # inf: flat bottom


def test_objective_is_finite_at_every_corner_of_the_box(fountas_problem):
    p = fountas_problem
    import itertools

    corners = [[t, *c] for t in range(9) for c in itertools.product(*zip(p.xl[1:], p.xu[1:]))]
    assert np.all(np.isfinite(p.evaluate(np.array(corners, float))))


def test_problem_pickles_and_evaluates_identically(fountas_problem):
    q = pickle.loads(pickle.dumps(fountas_problem))
    X = np.vstack([fountas_problem.row(GA), fountas_problem.row(VEGA)])
    np.testing.assert_array_equal(q.evaluate(X), fountas_problem.evaluate(X))


def test_runs_under_a_pymoo_algorithm():
    from pymoo.algorithms.soo.nonconvex.ga import GA as PymooGA
    from pymoo.optimize import minimize

    p = ToolpathProblem(normalization=FIXED)
    res = minimize(p, PymooGA(pop_size=10), ("n_gen", 3), seed=1)
    assert res.F.shape == (1,) and np.isfinite(res.F[0])


def test_multi_objective_mode_returns_normalized_columns():
    p = ToolpathProblem(objectives=["machining_error", "cc_count"], normalization=FIXED)
    X = np.vstack([p.row(GA), p.row(VEGA)])
    F = p.evaluate(X)
    crit = p.criteria(X)
    assert F.shape == (2, 2) and p.n_obj == 2
    np.testing.assert_allclose(F[:, 1], crit["cc_count"] / 2000.0)


def _apt_title(files) -> str:
    """The APT program's opening comment (the artifacts' title), unwrapped."""
    lines = files["toolpath.apt"].decode().splitlines()[1:]
    return " ".join(line[3:] for line in lines[:lines.index("$$ TOOLPOINT TIP")])


def test_artifacts_title_holds_the_plan_lengths_without_evaluating_criteria():
    """The title's cutting and Eq. 4 lengths are those the criteria report; a simulated
    problem writes its artifacts without running the cut simulation."""
    sim = ToolpathProblem(criteria="simulated", normalization=FIXED)

    def no_simulation(*args, **kwargs):
        raise AssertionError("artifacts ran the cut simulation")

    sim.simulated.measure = no_simulation
    crit = ToolpathProblem(normalization=FIXED).evaluate_params(GA)
    assert (f"5axis, single: 1 zone, cutting {crit['cutting_length']:.1f} mm, Eq. 4 total "
            f"{crit['eq4_total']:.1f} mm") in _apt_title(sim.artifacts(sim.row(GA)[0]))
    zoned = ToolpathProblem(surface="choi", machine="3axis", spacing="scallop",
                            fixed={"step": 3.0}, ranges={"zones": [1, 3]},
                            zoning={"method": "kmeans", "mesh": [10, 10]},
                            weights={"eq4_total": 1.0}, normalization={"eq4_total": [0, 1]})
    x = np.array([1.0, 3.0])
    crit = zoned.criteria(x[None])
    zones, cutting = crit["zones"][0], crit["cutting_length"][0]
    assert zones > 1 and crit["eq4_total"][0] == pytest.approx(cutting + (zones - 1) * 40.0)
    assert (f"3axis, kmeans with K = 3 gave {zones:.0f} zones, cutting {cutting:.1f} mm, Eq. 4 total "
            f"{cutting + (zones - 1) * 40.0:.1f} mm") in _apt_title(zoned.artifacts(x))


def test_plan_is_in_zigzag_order_with_consistent_tool_geometry(fountas_problem):
    batch, genes = fountas_problem.plan(fountas_problem.row(GA))
    path, labels = fountas_problem.cl_path(GA)
    assert labels is None and batch.n == 1 and genes["tool"][0] == 5  # tool id 6 = index 5
    assert len(batch.p) == len(path)
    assert batch.on_part.sum() == fountas_problem.evaluate_params(GA)["cc_count"]
    np.testing.assert_array_equal(path.info["cc"], batch.p)
    k = path.pass_index
    assert np.all(np.diff(k) >= 0) and k[0] == 0
    x0, x1 = batch.p[k == 0, 0], batch.p[k == 1, 0]
    assert np.all(np.diff(x0) > 0) and np.all(np.diff(x1) < 0)  # zig, then zag
    np.testing.assert_allclose(np.linalg.norm(batch.axis, axis=1), 1.0)
    lead, tilt = np.radians(3.379), np.radians(0.040)
    np.testing.assert_allclose(np.einsum("ij,ij->i", batch.axis, batch.normal), np.cos(lead) * np.cos(tilt))
    np.testing.assert_allclose(np.einsum("ij,ij->i", batch.axis, batch.tangent), np.sin(lead), atol=1e-12)
    # torus of tool 6 (R 8, r 3): the corner-circle centre of the contact lies on the rim
    # circle around the axis, r above the tip
    R, r = 8.0, 3.0  # (on the part: the run-on rows past the edge are lifted off their points)
    on = batch.on_part
    q = batch.p[on] + r * batch.normal[on]
    rel = q - (path.tip[on] + r * path.axis[on])
    np.testing.assert_allclose(np.einsum("ij,ij->i", rel, path.axis[on]), 0.0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(rel, axis=1), R - r, rtol=1e-9)


def test_choi_and_bspline_surfaces_from_plain_data(tmp_path):
    net = choi_poles()
    p = ToolpathProblem(surface={"type": "bspline", "poles": net.tolist(), "degree": [3, 3]},
                        normalization=FIXED)
    q = ToolpathProblem(surface="choi", normalization=FIXED)
    X = np.array([[5, 30.0, 2.0, 0.5, 6.0], [8, 20.0, 0.0, 0.0, 5.0]])
    np.testing.assert_allclose(p.evaluate(X), q.evaluate(X), rtol=1e-9)
    # the same net from each file format
    (tmp_path / "net.json").write_text(json.dumps({"poles": net.tolist()}))
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(net.tolist()))
    rows = ["i,j,x,y,z"] + [f"{i},{j},{x},{y},{z}" for i in range(4) for j in range(4)
                            for x, y, z in [net[i, j]]]
    (tmp_path / "net.csv").write_text("\n".join(rows))
    for name in ("net.json", "net.yaml", "net.csv"):
        r = ToolpathProblem(surface={"type": "bezier", "poles": name, "degree": [3, 3]},
                            base_dir=tmp_path, normalization=FIXED)
        u = np.linspace(0, 1, 7)
        np.testing.assert_allclose(r.surface.points(u, u[::-1]),
                                   choi_surface().points(u, u[::-1]), atol=1e-12)


def _error(**kw):
    with pytest.raises(ValueError) as exc:
        ToolpathProblem(**{"normalization": FIXED, **kw})
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


def test_bad_surfaces_raise_one_line_naming_the_key(tmp_path):
    net = choi_poles()
    assert _error(surface={"type": "bezier", "poles": net[:3].tolist(), "degree": [3, 3]}) == \
        "surface.poles: expected shape (4, 4, 3), got (3, 4, 3)"
    bad = net.copy()
    bad[1, 2, 0] = np.nan
    assert _error(surface={"type": "bezier", "poles": bad.tolist()}).startswith(
        "surface.poles: contains NaN or infinite values (first at [1][2][0])")
    assert _error(surface={"type": "bezier", "poles": [[1, 2], [3]]}).startswith("surface.poles:")
    assert _error(surface={"type": "nurbs"}).startswith("surface.poles: missing")
    assert _error(surface={"type": "cone"}).startswith("surface.type:")
    assert _error(surface={"type": "bezier", "poles": "missing.json"}, base_dir=tmp_path).startswith(
        "surface.poles: file not found")
    assert _error(surface={"type": "bspline", "poles": net.tolist(), "knots_u": [0, 1]}).startswith(
        "surface.knots_u: expected 8 knots")
    (tmp_path / "dup.csv").write_text("0,0,0,0,0\n0,0,1,1,1\n1,1,2,2,2\n0,1,0,1,0\n1,0,1,0,0\n")
    assert "given 2 times" in _error(surface={"type": "bezier", "poles": "dup.csv"}, base_dir=tmp_path)


def test_bad_tools_weights_and_settings_raise_one_line_naming_the_key():
    assert _error(tools=[{"diameter": 16, "corner_radius": 9}]) == \
        "tools[0].corner_radius: 9 exceeds the tool radius 8"
    assert _error(tools=[{"diameter": 8, "corner_radius": 1, "type": "ball"}]).startswith("tools[0].type:")
    assert _error(tools=[{"id": 1, "diameter": 8, "corner_radius": 0},
                         {"id": 1, "diameter": 8, "corner_radius": 4}]).startswith("tools: duplicate")
    assert _error(weights={"machining_error": 0.5, "cc_count": 0.4}).startswith(
        "weights: must sum to 1 (within 1e-9), got 0.9")
    assert _error(weights={"machining_error": 1.5, "cc_count": -0.5}).startswith(
        "weights.machining_error: must be in [0, 1]")
    assert _error(weights={"speed": 1.0}).startswith("weights.speed: unknown criterion")
    assert _error(feed_rate=0).startswith("feed_rate:")
    assert _error(tolerance=-0.01).startswith("tolerance:")
    assert _error(ranges={"lead": [5, 0]}).startswith("ranges.lead:")
    assert _error(ranges={"speed": [0, 1]}).startswith("ranges.speed:")
    # weights summing to 1 within 1e-9 are accepted
    ToolpathProblem(weights={"machining_error": 0.3, "cc_count": 0.7 + 5e-10}, normalization=FIXED)


def test_out_of_range_parameters_raise_one_line_naming_the_parameter(fountas_problem):
    p = fountas_problem
    for params, start in [({**VEGA, "lead": 7.0}, "params.lead: 7 outside [0, 5]"),
                          ({**VEGA, "stepover": 19.0}, "params.stepover: 19 outside [20, 45]"),
                          ({**VEGA, "tool": 10}, "params.tool: no tool with id 10"),
                          ({**VEGA, "speed": 1.0}, "params.speed: unknown parameter"),
                          ({k: v for k, v in VEGA.items() if k != "step"}, "params.step: missing")]:
        with pytest.raises(ValueError) as exc:
            p.evaluate_params(params)
        assert str(exc.value).startswith(start) and "\n" not in str(exc.value)
    with pytest.raises(ValueError, match=r"^params.tool: 9 outside 0 .. 8"):
        p.evaluate(np.array([[9.0, 30, 1, 1, 6]]))
    with pytest.raises(ValueError, match=r"^params.tilt: -0.5 outside \[0, 2\] \(row 1\)"):
        p.evaluate(np.array([[0.0, 30, 1, 1, 6], [0.0, 30, 1, -0.5, 6]]))
    assert np.isfinite(p.evaluate(np.array([[8.4, 45, 5, 2, 10]]))).all()  # index 8.4 rounds to 8


def test_an_empty_batch_evaluates_to_an_empty_result(fountas_problem):
    assert fountas_problem.evaluate(np.zeros((0, 5))).shape == (0, 1)
    assert all(len(v) == 0 for v in fountas_problem.criteria(np.zeros((0, 5))).values())
