"""``evoplan study`` as a user runs it: a good study's files, and bad input stopped in one line."""

from __future__ import annotations

import json
import subprocess
import sys

import pandas as pd
import pytest

from evoplan.cli import main

from .conftest import ROOT, SMALL


def test_a_study_writes_its_tables_figures_and_report(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(SMALL.replace("output: {plots: false}", "output: {plots: true}"))
    out = tmp_path / "res"
    proc = subprocess.run([sys.executable, "-m", "evoplan", "study", str(path), "--out", str(out)],
                          capture_output=True, text=True, timeout=120, env={"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg",
                                                                           "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout.strip().splitlines()[-1])["ran"] == 16
    for name in ("runs.csv", "summary.csv", "tests.csv", "report.md", "study.yaml", "execution.json",
                 "figures/convergence.png", "figures/final_values.png", "figures/ecdf.png"):
        assert (out / name).is_file(), name
    runs = pd.read_csv(out / "runs.csv")
    assert len(runs) == 16 and set(runs["algorithm"]) == {"ga", "vega", "pymoo_de", "deap_easimple"}
    assert {"algorithm", "problem", "dimension", "seed", "final_best", "evaluations", "wall_seconds",
            "failures", "status", "error"} <= set(runs.columns)
    assert (runs["final_best"] >= 0).all() and (runs["evaluations"] >= 120).all()
    summary = pd.read_csv(out / "summary.csv")
    assert len(summary) == 8 and {"median", "q1", "q3", "best", "mean_rank"} <= set(summary.columns)
    tests = pd.read_csv(out / "tests.csv")
    assert len(tests) == 6 and set(tests["reference"]) == {"ga"}
    report = (out / "report.md").read_text()
    assert "## kubota, 2-D" in report and "![figures/ecdf.png](figures/ecdf.png)" in report


BAD = {
    "unknown_algorithm": ("algorithms: [{name: pso}]", "algorithms[0].name: unknown algorithm 'pso'"),
    "unknown_problem": ("problems: [{name: kubotta}]", "unknown problem 'kubotta'"),
    "budget_zero": ("budget: {evaluations: 0}", "budget.evaluations"),
    "no_budget": ("budget: {}", "budget"),
    "bad_adapter_setting": ("algorithms: [{name: pymoo_de, CR: 3}]", "algorithms[0].CR"),
    "dimension_on_fixed_problem": ("problems: [{name: kubota, dimensions: [10]}]", "problems[0]: dimensions: problem 'kubota' does not take n_var"),
    "bad_level": ("factors: {algorithm: vega, vary: {virus.infection_rate: [0.05]}}",
                  "factors.vary.virus.infection_rate[0]"),
    "unknown_reference": ("statistics: {reference: cmaes}", "statistics.reference"),
    "duplicate_label": ("algorithms: [{name: ga}, {name: ga}]", "algorithms[1]"),
    "unknown_key": ("seedz: 3", "seedz"),
}


def study_text(change: str) -> str:
    base = {"seeds": "seeds: 2", "budget": "budget: {evaluations: 100}", "problems": "problems: [{name: kubota}]",
            "algorithms": "algorithms: [{name: ga}, {name: vega}]"}
    key = change.split(":")[0]
    base[key] = change
    return "\n".join(base.values()) + "\n"


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_study_is_one_line_exit_2_and_no_folder(case, tmp_path, capsys):
    change, expected = BAD[case]
    path = tmp_path / "bad.yaml"
    path.write_text(study_text(change))
    out = tmp_path / "res"
    assert main(["study", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("evoplan: error: ") and expected in err, err
    assert str(path) in err
    assert not out.exists()


def test_a_scheduler_that_does_not_answer_stops_before_any_run(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(study_text("seeds: 1"))
    out = tmp_path / "res"
    proc = subprocess.run([sys.executable, "-m", "evoplan", "study", str(path), "--out", str(out),
                           "--backend", "dask", "--scheduler", "tcp://127.0.0.1:1"],
                          capture_output=True, text=True, timeout=60, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [proc.stderr.strip()]
    assert "tcp://127.0.0.1:1: no Dask scheduler answers" in proc.stderr
    assert not out.exists()


@pytest.mark.parametrize("args,expected", [(["--backend", "processes", "--scheduler", "tcp://x:1"],
                                            "--scheduler is for --backend dask, not processes"),
                                           (["--backend", "processes", "--workers", "0"], "--workers must be")])
def test_bad_options_are_one_line(args, expected, tmp_path, capsys):
    path = tmp_path / "s.yaml"
    path.write_text(study_text("seeds: 1"))
    assert main(["study", str(path), "--out", str(tmp_path / "r"), *args]) == 2
    assert expected in capsys.readouterr().err and not (tmp_path / "r").exists()


def test_a_folder_of_another_study_is_refused(tmp_path, capsys):
    path = tmp_path / "one.yaml"
    path.write_text(study_text("seeds: 1"))
    out = tmp_path / "res"
    assert main(["study", str(path), "--out", str(out), "--quiet"]) == 0
    other = tmp_path / "two.yaml"
    other.write_text(study_text("seeds: 1"))
    capsys.readouterr()
    assert main(["study", str(other), "--out", str(out), "--quiet"]) == 2
    assert "holds the study 'one', not 'two'" in capsys.readouterr().err
