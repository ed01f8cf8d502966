"""A study run again on its finished folder re-analyzes only what changed: each figure and
bayes.csv is keyed by a hash of its inputs (analysis.json counts what was rebuilt and reused)."""

from __future__ import annotations

import json

from evoplan.study.config import load_study
from evoplan.study import memo
from evoplan.study.memo import AnalysisMemo, code_digest
from evoplan.study.runner import run_study

STUDY = """
seed: 1
seeds: 3
budget: {{evaluations: 150}}
problems: [{{name: kubota}}]
algorithms:
  - {{name: ga, population: 10}}
  - {{name: vega, population: 10}}
  - {{name: ga, label: ga_tournament, population: 10, selection: {{kind: tournament}}}}
statistics: {{rope: {rope}, alpha: {alpha}}}
output: {{plots: true}}
"""
FIGURES = ["figures/convergence.png", "figures/final_values.png", "figures/ecdf.png", "figures/critical_difference.png"]
COSTLY = FIGURES + ["bayes.csv", "ioh"]


def analyze(tmp_path, rope=0.0, alpha=0.05):
    path = tmp_path / "study.yaml"
    path.write_text(STUDY.format(rope=rope, alpha=alpha))
    execution = run_study(load_study(path), str(path), tmp_path / "out", "serial", progress=False)
    last = json.loads((tmp_path / "out" / "analysis.json").read_text())["last"]
    files = {name: (tmp_path / "out" / name).read_bytes() for name in FIGURES + ["bayes.csv", "report.md"]}
    return execution, last, files


def _without_invocations(report: bytes) -> list[str]:
    return [ln for ln in report.decode().splitlines() if not ln.startswith("- runs made")]


def test_a_second_run_rebuilds_nothing_and_a_changed_setting_only_its_outputs(tmp_path):
    first, last, files = analyze(tmp_path)
    ioh_files = sorted(p.name for p in (tmp_path / "out" / "ioh").rglob("*"))
    assert len(ioh_files) >= 6  # a folder, a meta-data file and a data folder and file per variant
    assert first["ran"] == 9 and sorted(last["rebuilt"]) == sorted(COSTLY) and last["reused"] == []
    again, last, same = analyze(tmp_path)
    assert again["ran"] == 0 and again["reused"] == 9
    assert last["rebuilt"] == [] and sorted(last["reused"]) == sorted(COSTLY)
    assert all(same[n] == files[n] for n in FIGURES + ["bayes.csv"])
    assert sorted(p.name for p in (tmp_path / "out" / "ioh").rglob("*")) == ioh_files
    assert _without_invocations(same["report.md"]) == _without_invocations(files["report.md"])  # bayes read back
    _, last, rope = analyze(tmp_path, rope=0.01)  # the rope changes the Bayesian test only
    assert last["rebuilt"] == ["bayes.csv"] and rope["bayes.csv"] != files["bayes.csv"]
    _, last, _ = analyze(tmp_path, rope=0.01, alpha=0.1)  # alpha: the critical-difference diagram
    assert last["rebuilt"] == ["figures/critical_difference.png"]
    (tmp_path / "out" / "figures" / "ecdf.png").unlink()  # a missing output is made again
    _, last, _ = analyze(tmp_path, rope=0.01, alpha=0.1)
    assert last["rebuilt"] == ["figures/ecdf.png"]


def test_a_code_change_rebuilds_every_output(tmp_path, monkeypatch):
    analyze(tmp_path)
    assert AnalysisMemo(tmp_path / "out").code == code_digest()
    monkeypatch.setattr(memo, "code_digest", lambda: "the modules' source changed")
    _, last, _ = analyze(tmp_path)
    assert sorted(last["rebuilt"]) == sorted(COSTLY)
