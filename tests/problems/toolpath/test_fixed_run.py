"""A run file with every gene fixed: that plan evaluated once, its folder written like a run's."""

from __future__ import annotations

import json

import numpy as np
import pytest

from evoplan.cli import main
from evoplan.problems.toolpath import ToolpathProblem

PLAN = {"tool": 6, "stepover": 41.729, "lead": 2.957, "tilt": 0.027, "step": 6.338}
RUN = """
seed: 3
problem:
  name: toolpath
  params:
    surface: fountas
    weights: {{machining_error: 0.5, cc_count: 0.5}}
    tolerance: 0.01
    fixed: {fixed}
{normalization}algorithm: {{name: vega, population: 20, virus: {{count: 3}}}}
termination: {{generations: 50}}
"""


def _run_file(tmp_path, normalization=""):
    fixed = "{" + ", ".join(f"{k}: {v}" for k, v in PLAN.items()) + "}"
    path = tmp_path / "fixed.yaml"
    path.write_text(RUN.format(fixed=fixed, normalization=normalization))
    return path


def test_every_gene_fixed_evaluates_the_plan_once(tmp_path, capsys, monkeypatch):
    calls = []
    original = ToolpathProblem._criteria_of
    monkeypatch.setattr(ToolpathProblem, "_criteria_of", lambda self, X: calls.append(len(X)) or original(self, X))
    out = tmp_path / "run"
    assert main(["run", str(_run_file(tmp_path)), "--out", str(out), "--quiet"]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary["evaluations"] == 1 and summary["stop_reason"] == "fixed"
    assert calls == [1]  # no normalization design, no second evaluation for the report
    names = {p.name for p in out.iterdir()}
    assert {"config.yaml", "history.csv", "best.json", "toolpath.apt", "zone_map.png"} <= names
    assert not any(n.startswith(".") or n == "checkpoint.npz" for n in names)
    best = json.loads((out / "best.json").read_text())
    assert best["plan"] == pytest.approx(PLAN)
    c = best["criteria"]
    assert c["cc_count"] == 289 and c["n_passes"] == 17  # the published VEGA plan: 17 x 17
    # no design to normalize over: Eq. 9 over the raw criteria
    assert best["objective"] == pytest.approx(0.5 * c["machining_error"] + 0.5 * c["cc_count"])
    assert (out / "history.csv").read_text().count("\n") == 2  # header + one row


def test_a_fixed_run_matches_evaluate_of_the_same_plan(tmp_path, capsys):
    norm = "    normalization: {machining_error: [0, 2], cc_count: [0, 1000]}\n"
    out = tmp_path / "run"
    assert main(["run", str(_run_file(tmp_path, norm)), "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    best = json.loads((out / "best.json").read_text())
    assert main(["evaluate", str(tmp_path / "fixed.yaml")]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["criteria"] == pytest.approx(best["criteria"])
    assert report["objective"] == pytest.approx(best["objective"])
    assert best["objective"] == pytest.approx(0.5 * best["criteria"]["machining_error"] / 2
                                              + 0.5 * best["criteria"]["cc_count"] / 1000)
    # the same folder again, and a resume: one line each, exit 2
    assert main(["run", str(tmp_path / "fixed.yaml"), "--out", str(out), "--quiet"]) == 2
    assert main(["run", str(tmp_path / "fixed.yaml"), "--resume", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "every decision is fixed" in err[1]


def test_a_one_point_range_fixes_its_gene():
    # ranges {stepover: [v, v]} was refused ("expected finite lo < hi"): it is the plan's value
    point = ToolpathProblem(ranges={k: [v, v] for k, v in PLAN.items() if k != "tool"}, fixed={"tool": 6})
    fixed = ToolpathProblem(fixed=PLAN)
    assert point.fixed == fixed.fixed and point.genes.free == () == fixed.genes.free
    assert point.genes.design(8, 0).shape == (1, 0)  # one plan: it raised "cannot reshape array of size 0"
    a, b = (p.criteria(np.zeros((1, 0))) for p in (point, fixed))
    assert a["cc_count"][0] == b["cc_count"][0] == 289 and a["path_length"][0] == b["path_length"][0]
    one = ToolpathProblem(ranges={"stepover": [30, 30]})
    assert one.fixed == {"stepover": 30.0} and "stepover" not in one.genes.free
    with pytest.raises(ValueError, match=r"^ranges.stepover: expected finite lo < hi"):
        ToolpathProblem(ranges={"stepover": [31, 30]})


def test_the_tool_alone_free_is_normalized_over_every_tool():
    # every continuous gene fixed, the tool free: the design is one row per tool and the
    # random rows (was: "cannot reshape array of size 0" when the problem was built)
    fixed = {k: v for k, v in PLAN.items() if k != "tool"}
    problem = ToolpathProblem(surface="fountas", tolerance=0.01, fixed=fixed)
    assert tuple(problem.genes.free) == ("tool",)
    design = problem.genes.design(4, 0)
    assert design.shape == (len(problem.tool_db.tools) + 4, 1)
    assert set(design[:len(problem.tool_db.tools), 0]) == set(range(len(problem.tool_db.tools)))
    f = problem.evaluate(np.array([[0.0], [5.0]]))
    assert f.shape == (2, 1) and np.isfinite(f).all() and f[0, 0] != f[1, 0]
