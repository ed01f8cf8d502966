"""The one ``problem: toolpath``: its configurations, genes (free or fixed), errors and runs."""

from __future__ import annotations

import json

import engine_rows
import numpy as np
import pytest
import yaml

from evoplan.problems.toolpath import ToolpathProblem
from evoplan.problems.toolpath.tools import CHOI_TOOLS
from tests.choi_zoning import choi_zoning
from tests.test_cli import evoplan, write

NORM = {"machining_error": [0.0, 1.0], "cc_count": [0.0, 2000.0]}
ZONED = dict(surface="choi", tools=CHOI_TOOLS[:2], machine="5axis", feed_angle="optimized",
             zoning={"method": "kmeans", "mesh": [12, 12], "merge": False}, normalization=NORM)


@pytest.fixture(scope="module")
def zoned():
    """Choi, 5-axis, K-means zones: all six genes free."""
    return ToolpathProblem(**ZONED)


def test_all_genes_decode_in_chromosome_order(zoned, fountas_problem):
    assert list(zoned.variables) == ["tool", "stepover", "lead", "tilt", "step", "zones"]
    assert zoned.n_var == 6 and zoned.fixed == {}
    np.testing.assert_array_equal(zoned.xl, [0, 20, 0, 0, 5, 1])
    np.testing.assert_array_equal(zoned.xu, [1, 45, 5, 2, 10, 8])
    X = np.array([[1.4, 30.0, 2.5, 1.0, 6.0, 2.6]])
    genes = zoned.genes.decode(X)
    assert genes["tool"].tolist() == [1] and genes["zones"].tolist() == [3.0]  # rounded
    assert genes["stepover"][0] == 30.0 and genes["lead"][0] == 2.5 and genes["tilt"][0] == 1.0
    assert genes["step"][0] == 6.0
    assert zoned.genes.named(X[0]) == {"tool": 2, "stepover": 30.0, "lead": 2.5, "tilt": 1.0,
                                       "step": 6.0, "zones": 3}
    # the plan reads every gene: the tool's diameter scales the spacing, the step the points
    batch, _ = fountas_problem.plan(np.array([[5, 41.7, 3, 0, 5.0], [5, 41.7, 3, 0, 9.5]]))
    longest = [batch.seg_len[batch.seg_ind == i].max() for i in (0, 1)]
    assert longest[0] <= 5 + 1e-9 < longest[1] <= 9.5 + 1e-9  # the step bounds the CC spacing
    crit = zoned.criteria(np.array([[1, 30, 2, 0, 6, 1], [1, 30, 2, 0, 6, 4]]))
    assert crit["zones"][0] == 1 and crit["zones"][1] >= 2
    np.testing.assert_allclose(crit["eq4_total"], crit["cutting_length"] + (crit["zones"] - 1) * 40)


def test_a_fixed_gene_leaves_the_chromosome_and_the_plan_uses_its_value():
    p = ToolpathProblem(**{**ZONED, "fixed": {"lead": 3.0, "tool": 2, "zones": 1}})
    assert list(p.variables) == ["stepover", "tilt", "step"] and p.n_var == 3
    assert p.fixed == {"lead": 3.0, "tool": 2, "zones": 1}
    np.testing.assert_array_equal(p.xl, [20, 0, 5])
    genes = p.genes.decode(np.array([[30.0, 0.0, 6.0]]))
    assert genes["lead"].tolist() == [3.0] and genes["tool"].tolist() == [1]
    batch, _ = p.plan(np.array([[30.0, 0.0, 6.0]]))
    lead = np.degrees(np.arcsin(np.einsum("ij,ij->i", batch.axis, batch.tangent)))
    np.testing.assert_allclose(lead, 3.0, atol=1e-9)
    # the same plan as the free problem given the fixed values
    free = ToolpathProblem(**ZONED)
    c_fixed = p.evaluate_params({"stepover": 30, "tilt": 0, "step": 6})
    c_free = free.evaluate_params({"tool": 2, "stepover": 30, "lead": 3, "tilt": 0, "step": 6,
                                   "zones": 1})
    assert c_fixed == c_free
    # a fixed gene may be named with its own value only
    assert p.evaluate_params({"stepover": 30, "tilt": 0, "step": 6, "lead": 3}) == c_fixed
    with pytest.raises(ValueError, match=r"^params.lead: fixed at 3 by the problem's config$"):
        p.evaluate_params({"stepover": 30, "tilt": 0, "step": 6, "lead": 4})


def _error(**kw):
    with pytest.raises(ValueError) as exc:
        ToolpathProblem(**{"normalization": NORM, **kw})
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


def test_bad_configurations_are_one_line_naming_the_key():
    z = {"method": "kmeans", "mesh": [8, 8]}
    assert _error(machine="4axis").startswith("machine: expected one of 5axis, 3axis")
    assert _error(machine="3axis", ranges={"lead": [0, 3]}) == \
        "ranges.lead: not a gene of this configuration (machine 3axis has no lead/tilt)"
    assert _error(ranges={"zones": [1, 3]}) == \
        "ranges.zones: not a gene of this configuration (zoning method single has no gene)"
    assert _error(zoning=z, fixed={"k_lz": 0.2}).startswith(
        "fixed.k_lz: not a gene of this configuration (zoning method kmeans's gene is zones)")
    assert _error(machine="3axis", spacing="scallop", fixed={"stepover": 30}).startswith(
        "fixed.stepover: not a gene of this configuration (spacing scallop")
    assert _error(fixed={"tilt": 95}) == "fixed.tilt: angles must lie in (-90, 90) degrees, got 95"
    assert _error(fixed={"tool": 12}).startswith("fixed.tool: no tool with id 12")
    assert _error(zoning=z, fixed={"zones": 0}).startswith("fixed.zones: ")
    assert _error(zoning=z, fixed={"zones": 2.5}) == "fixed.zones: expected an integer, got 2.5"
    assert _error(zoning=z, ranges={"zones": [1, 65]}).startswith(
        "ranges.zones: expected integers in [1, 64]")
    assert _error(ranges={"lead": 0}).startswith("ranges.lead: expected [lo, hi], got 0 (to fix")
    assert _error(ranges={"lead": [0, 1]}, fixed={"lead": 0}).startswith("ranges.lead: lead is fixed")
    assert _error(ranges={"tool": [1, 2]}).startswith("ranges.tool: the tool is a choice")
    assert _error(fixed={"speed": 1}).startswith("fixed.speed: unknown gene")
    assert _error(zoning={"method": "voronoi"}).startswith("zoning.method: expected one of")
    assert _error(zoning={"method": "kmeans", "colour": 1}).startswith("zoning.colour: unknown")
    assert _error(zoning={**z, "settings": {"K": 3}}).startswith(
        "zoning.settings.K: set by the gene zones (fix it with fixed: {zones: 3})")
    assert _error(zoning={**z, "merge": {"min_zone_area": 2}}).startswith("zoning.merge.min_zone_area:")
    assert _error(zoning={**z, "mesh": [0, 5]}).startswith("zoning.mesh: a mesh needs")
    assert _error(feed_angle="sideways").startswith("feed_angle: expected a number of degrees")
    assert _error(placement="drop").startswith("placement: only a 3-axis machine")
    assert _error(spacing="helical").startswith("spacing: expected one of stepover, scallop")
    assert _error(weights={"objective": 1}).startswith("weights.objective:")


def test_single_zone_gives_the_engines_numbers_on_the_table2_sets(fountas_problem):
    # the problem adds nothing to the engine's criteria of a plan: on Fountas' Table 2 sets
    # (whose criteria test_analytic_criteria.py pins to the former evaluator's figures) the
    # problem's criteria are the engine's, bit for bit, with and without the edge run-on
    rows = np.array([[5, 30.791, 3.379, 0.040, 8.451], [5, 41.729, 2.957, 0.027, 6.338]])
    surface, tools = fountas_problem.surface, fountas_problem.tool_db
    for overrun in (False, True):
        problem = ToolpathProblem(normalization=fountas_problem.norm_bounds,
                                  edge_overrun=overrun)
        got = problem.criteria(rows)
        want = engine_rows.criteria(surface, tools, rows, edge_overrun=overrun)
        for name, value in want.items():
            np.testing.assert_array_equal(got[name], value, err_msg=name)
        if not overrun:
            assert got["cc_count"].tolist() == [361, 289] and got["n_passes"].tolist() == [22, 17]


def test_the_zoned_configuration_minimizes_the_eq4_total():
    """Choi's zoned 3-axis configuration (the removed ``toolpath_zoning`` problem's): the
    tool and K free, F is Djebali's Eq. 4 total in mm."""
    new = ToolpathProblem(**choi_zoning(mesh=(10, 10), gene_range=(1, 3)))
    assert list(new.variables) == ["tool", "zones"]
    X = np.array([[0, 1], [1, 2]], float)
    c = new.criteria(X)
    # eq4_total is Djebali's Eq. 4, recomputed here from the plan's polylines: the
    # sections' lengths plus (zones - 1) delta_l (40 mm)
    batch, _ = new.plan(X, place=False)
    cutting = np.zeros(len(X))
    for s in range(len(batch.sec_start)):
        pts = batch.p[batch.sec_start[s]:batch.sec_start[s] + batch.sec_count[s]]
        cutting[batch.sec_ind[s]] += np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()
    assert c["zones"].tolist() == [1.0, 2.0]
    np.testing.assert_allclose(c["eq4_total"], cutting + [0.0, 40.0], rtol=1e-12)
    np.testing.assert_array_equal(new.evaluate(X)[:, 0], c["eq4_total"])  # F in mm
    with pytest.raises(ValueError, match=r"^ranges.zones: expected integers in \[1, 100\]"):
        ToolpathProblem(**choi_zoning(mesh=(10, 10), gene_range=(1, 101)))
    with pytest.raises(ValueError, match=r"^weights.total_length: renamed eq4_total$"):
        ToolpathProblem(**choi_zoning(mesh=(10, 10), weights={"total_length": 1.0}))


def test_the_removed_zoning_problem_names_its_new_form(tmp_path):
    cfg = write(tmp_path / "old.yaml", "problem: {name: toolpath_zoning, params: {mesh: [10, 10]}}\n"
                "algorithm: {name: ga, population: 4}\ntermination: {generations: 1}\n")
    proc = evoplan("run", cfg, "--out", tmp_path / "out")
    code, err = proc.returncode, proc.stderr
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert "toolpath_zoning: removed, write name: toolpath with machine: 3axis" in err
    assert not (tmp_path / "out").exists()


RUN = """
seed: 1
problem:
  name: toolpath
  params: {params}
algorithm: {{name: vega, population: 4, virus: {{count: 1}}}}
termination: {{generations: 2}}
"""
CHOI_3AXIS = ("{surface: choi, tools: [{id: 1, type: ball, diameter: 6.35}], machine: 3axis, "
              "spacing: scallop, zoning: {method: kmeans, mesh: [12, 12]}, feed_angle: optimized, "
              "ranges: {zones: [1, 3]}, fixed: {step: 2}, weights: {eq4_total: 1}, "
              "normalization: {eq4_total: [0, 1]}}")


def _run(tmp_path, params):
    """(best.json, toolpath.apt lines) of a tiny run of ``params``; both PNGs are written."""
    out = tmp_path / "res"
    proc = evoplan("run", write(tmp_path / "r.yaml", RUN.format(params=params)),
                   "--out", out)
    assert proc.returncode == 0, proc.stderr
    for name in ("zone_map.png", "cc_pattern.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"
    return (json.loads((out / "best.json").read_text()),
            (out / "toolpath.apt").read_text().splitlines())


def test_a_zoned_3axis_run_writes_its_plan_files(tmp_path):
    best, apt = _run(tmp_path, CHOI_3AXIS)
    assert set(best["variables"]) == {"zones"} and best["objective"] > 100  # mm; one tool: fixed
    assert "TLAXIS/0,0,1" in apt and any(line.startswith("$$ ZONE 0 PASS 0") for line in apt)


FOUNTAS_5AXIS = ("{surface: fountas, tools: [{id: 6, type: toroidal, diameter: 16, corner_radius: 3}, "
                 "{id: 9, type: ball, diameter: 16}], zoning: {method: kmeans, mesh: [10, 10]}, "
                 "feed_angle: optimized, ranges: {zones: [2, 3]}, fixed: {tilt: 0}, "
                 "weights: {machining_error: 0.5, eq4_total: 0.5}, "
                 "normalization: {machining_error: [0, 1], eq4_total: [1000, 3000]}}")


def test_a_zoned_5axis_run_with_a_fixed_tilt_writes_a_multi_axis_plan(tmp_path):
    best, apt = _run(tmp_path, FOUNTAS_5AXIS)
    assert set(best["variables"]) == {"tool", "stepover", "lead", "step", "zones"}  # no tilt
    assert "MULTAX/ON" in apt
    zones = {line.split()[2] for line in apt if line.startswith("$$ ZONE ")}
    problem = ToolpathProblem(**yaml.safe_load(FOUNTAS_5AXIS))
    crit = problem.evaluate_params(best["variables"])
    assert len(zones) == crit["zones"] and crit["objective"] == pytest.approx(best["objective"])
