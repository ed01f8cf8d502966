"""Every command on the sample STEP part (runs/parts/sculpted_block.step), with small budgets:
run, evaluate, simulate, zone and machine; and ``evoplan examples`` ships the part."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

pytest.importorskip("OCP")

from tests.test_cli import evoplan, write  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
PART = ROOT / "runs" / "parts" / "sculpted_block.step"
SURFACE = f"{{type: step, file: {PART}, face: largest}}"

RUN = f"""
seed: 3
problem:
  name: toolpath
  params:
    surface: {SURFACE}
    tools: [{{id: 1, type: ball, diameter: 10}}]
    machine: 3axis
    tolerance: 0.02
    ranges: {{stepover: [30, 45], step: [4, 8]}}
    weights: {{machining_error: 0.5, cc_count: 0.5}}
    normalization: {{machining_error: [0, 0.1], cc_count: [100, 2000]}}
algorithm: {{name: vega, population: 4, virus: {{count: 1}}}}
termination: {{generations: 1}}
"""

ZONE = f"""
name: step_zone
surface: {SURFACE}
cutter: {{R: 5.0, r: 5.0}}
h_c: 0.05
mesh: [12, 12]
method: kmeans
seed: 0
kmeans: {{K: 2}}
"""


def test_run_evaluate_simulate_and_zone_work_on_the_step_face(tmp_path):
    cfg = write(tmp_path / "step.yaml", RUN)
    proc = evoplan("run", cfg, "--out", tmp_path / "res")
    assert proc.returncode == 0, proc.stderr
    apt = (tmp_path / "res" / "toolpath.apt").read_text()
    assert apt.count("GOTO/") > 100
    proc = evoplan("evaluate", cfg, "--set", "stepover=40", "--set", "step=6")
    assert proc.returncode == 0, proc.stderr
    crit = json.loads(proc.stdout)["criteria"]
    assert crit["cc_count"] > 100 and crit["chord_error_max"] <= 0.02 + 1e-9
    proc = evoplan("simulate", "--run", tmp_path / "res", "--out", tmp_path / "sim",
                   "--grid", "1.0", "--quiet")
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "sim").is_dir() and any((tmp_path / "sim").iterdir())
    proc = evoplan("zone", write(tmp_path / "zone.yaml", ZONE), "--out", tmp_path / "zone",
                   "--quiet")
    assert proc.returncode == 0, proc.stderr
    assert any((tmp_path / "zone").iterdir())


def test_the_shipped_machine_job_runs_on_the_step_face(tmp_path):
    job = yaml.safe_load((ROOT / "runs" / "step_block_machine.yaml").read_text())
    job["surface"]["file"] = str(PART)
    job["stock"]["cell"] = 2.0  # a coarse stock Z-map: the test is that it runs
    job["semifinish"]["stepover"] = 8.0
    proc = evoplan("machine", write(tmp_path / "m.yaml", yaml.safe_dump(job)), "--out",
                   tmp_path / "m")
    assert proc.returncode == 0, proc.stderr
    summary = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert {"roughing", "semifinish", "finish"} <= set(summary)
    assert (tmp_path / "m" / "finish.nc").stat().st_size > 1000


def test_examples_lists_the_step_runs_and_copies_the_part(tmp_path):
    proc = evoplan("examples")
    assert "step_block_zoned_vega " in proc.stdout and "step_block_machine " in proc.stdout
    proc = evoplan("examples", "step_block_zoned_vega", "--out", tmp_path)
    assert proc.returncode == 0, proc.stderr
    copied = tmp_path / "parts" / "sculpted_block.step"
    assert copied.read_bytes() == PART.read_bytes()
    surface = yaml.safe_load((tmp_path / "step_block_zoned_vega.yaml").read_text())
    assert surface["problem"]["params"]["surface"]["file"] == "parts/sculpted_block.step"
