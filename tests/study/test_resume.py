"""A study killed midway resumes and runs only the missing cells; a crashed run is a failed row."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pandas as pd

from evoplan.study.config import load_study
from evoplan.study.runner import run_study

from .conftest import ROOT

SLOW = """
seed: 5
seeds: 3
budget: {generations: 4}
problems:
  - {name: "tests.blackboxes:Slow", params: {delay: 0.06}}
  - {name: kubota}
algorithms:
  - {name: ga, population: 8}
  - {name: vega, population: 8, virus: {count: 2}}
output: {plots: false}
"""


def numbers(out) -> pd.DataFrame:
    return pd.read_csv(out / "runs.csv").drop(columns=["wall_seconds"])


def test_a_killed_study_resumes_with_only_the_missing_cells(tmp_path):
    path = tmp_path / "slow.yaml"
    path.write_text(SLOW)
    out = tmp_path / "killed"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    proc = subprocess.Popen([sys.executable, "-m", "evoplan", "study", str(path), "--out", str(out), "--quiet"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 60
    while time.time() < deadline and len(list((out / "cells").glob("*.json"))) < 3:
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = len(list((out / "cells").glob("*.json")))
    assert 3 <= done < 12, "the study should have been killed midway"
    study = load_study(path)
    execution = run_study(study, str(path), out, progress=False)
    assert execution["reused"] == done and execution["ran"] == 12 - done
    fresh = tmp_path / "fresh"
    run_study(study, str(path), fresh, progress=False)
    pd.testing.assert_frame_equal(numbers(out), numbers(fresh))
    again = run_study(study, str(path), out, progress=False)  # complete: nothing runs, analysis only
    assert again["ran"] == 0 and again["reused"] == 12


def test_changed_settings_rerun_only_the_cells_they_change(small_study, tmp_path):
    out = tmp_path / "out"
    run_study(load_study(small_study), str(small_study), out, progress=False)
    changed = small_study.read_text().replace("{name: pymoo_de, pop_size: 10}", "{name: pymoo_de, pop_size: 12}")
    small_study.write_text(changed)
    execution = run_study(load_study(small_study), str(small_study), out, progress=False)
    assert execution["ran"] == 4 and execution["reused"] == 12  # 2 problems x 2 seeds of pymoo_de


def test_a_crashing_run_is_recorded_as_failed_and_the_study_goes_on(small_study, tmp_path, monkeypatch):
    from evoplan.adapters.deap_easimple import DeapEaSimple

    def broken(self, f):
        raise FloatingPointError("the adapter blew up")

    monkeypatch.setattr(DeapEaSimple, "tell", broken)
    out = tmp_path / "out"
    execution = run_study(load_study(small_study), str(small_study), out, progress=False)
    runs = pd.read_csv(out / "runs.csv")
    failed = runs[runs["status"] == "failed"]
    assert execution["failed"] == 4 and set(failed["algorithm"]) == {"deap_easimple"}
    assert (failed["error"] == "FloatingPointError: the adapter blew up").all()
    assert (runs.loc[runs["status"] == "ok", "final_best"].notna()).all() and len(runs) == 16
    assert "## Failed runs" in (out / "report.md").read_text()
    summary = pd.read_csv(out / "summary.csv").set_index("algorithm")
    assert summary.loc["deap_easimple", "failed"].tolist() == [2, 2]
    monkeypatch.undo()
    execution = run_study(load_study(small_study), str(small_study), out, progress=False)
    assert execution["ran"] == 4 and execution["failed"] == 0  # failed cells run again on resume
    log = json.loads((out / "execution.json").read_text())  # one entry per invocation
    assert [(e["ran"], e["reused"]) for e in log] == [(16, 0), (4, 12)]


def test_runs_record_the_best_variables():
    from evoplan.study.cell import run_cell
    from evoplan.study.config import parse_study
    from evoplan.study.grid import build_grid

    study = parse_study({"seeds": 1, "budget": {"generations": 3}, "problems": [{"name": "kubota"}],
                         "algorithms": [{"name": "ga", "population": 10}, {"name": "pymoo_de", "pop_size": 10}]})
    for cell in build_grid(study):
        record, *_ = run_cell(cell)
        variables = json.loads(record["best_variables"])
        assert set(variables) == {"x", "y"} and all(-1 <= v <= 1 for v in variables.values())
