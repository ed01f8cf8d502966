"""Every folder writer (simulate, evaluate --out, run, machine, zone, study) on a full disk and killed
mid-write: one line, no folder that looks finished, no stale temporary blocking the next ``--out``."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from evoplan.folder_writer import write_folder

from .corpus import MACHINE, STUDY, ZONE

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
SIM = ["--set", "tool=8", "--set", "stepover=30.0", "--set", "lead=1.0", "--set", "tilt=0.5", "--set", "step=8.0",
       "--grid", "0.5"]


def command(tmp_path: Path, name: str) -> list[str]:
    if name == "simulate":
        return ["simulate", str(ROOT / "runs/fountas_toolpath_vega.yaml"), *SIM]
    if name == "evaluate":  # criteria.json, toolpath.apt, the zone map and the NC program
        return ["evaluate", str(ROOT / "runs/fountas_toolpath_vega.yaml"), *SIM[:-2], "--post", "fanuc"]
    if name == "run":
        return ["run", str(ROOT / "runs/kubota_vega.yaml"), "--quiet"]
    text = {"machine": MACHINE, "zone": ZONE, "study": STUDY}[name]
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    return [name, str(path)]


def evoplan(args, **kw):
    return subprocess.run([sys.executable, "-m", "evoplan", *args], capture_output=True, text=True, env=ENV,
                          timeout=300, **kw)


@pytest.fixture
def small_disk(tmp_path):
    disk = tmp_path / "disk"
    disk.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(disk)], capture_output=True).returncode:
        pytest.skip("mounting a small tmpfs needs privileges this machine does not give")
    try:
        yield disk
    finally:
        subprocess.run(["umount", str(disk)], capture_output=True)


@pytest.mark.parametrize("name", ["simulate", "evaluate", "run", "machine", "zone", "study"])
def test_a_full_disk_is_one_line_and_no_partial_folder(tmp_path, small_disk, name):
    out = small_disk / "out"
    proc = evoplan([*command(tmp_path, name), "--out", str(out)])
    assert proc.returncode != 0 and "Traceback" not in proc.stderr, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "No space left" in proc.stderr, proc.stderr
    if name == "study" and out.exists():  # a study is resumable cell by cell, like a run's checkpoint
        assert "resume" in proc.stderr and (out / "study.yaml").is_file()
    elif name == "run" and out.exists():  # a run keeps its last checkpoint, and says how to go on
        assert "--resume" in proc.stderr and (out / "checkpoint.npz").is_file() and not (out / "best.json").exists()
    else:
        assert list(small_disk.iterdir()) == [], list(small_disk.iterdir())


def test_the_writer_on_injected_enospc_leaves_nothing(tmp_path, monkeypatch):
    calls = []

    def full(fd):
        calls.append(fd)
        if len(calls) == 2:
            raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    from evoplan.errors import EvoplanError
    with pytest.raises(EvoplanError, match="No space left on device"):
        write_folder(tmp_path / "out", {"a.json": b"{}", "b.png": b"x" * 10})
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["simulate", "machine", "zone"])
def test_a_kill_mid_write_leaves_no_finished_looking_folder(tmp_path, name):
    """SIGKILL while the files are written (fsync slowed down): ``out`` does not exist, and the
    next writer into the same ``--out`` succeeds and removes the dead writer's partial folder."""
    out = tmp_path / "out"
    slow = tmp_path / "slow"
    slow.mkdir()
    (slow / "sitecustomize.py").write_text("import os, time\n_f = os.fsync\n"
                                           "def fsync(fd):\n    time.sleep(0.5)\n    _f(fd)\nos.fsync = fsync\n")
    env = {**ENV, "PYTHONPATH": f"{slow}:{ROOT}"}
    proc = subprocess.Popen([sys.executable, "-m", "evoplan", *command(tmp_path, name), "--out", str(out)],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 240
    while time.time() < deadline and not any(p.glob("*") for p in tmp_path.glob(".out.*.partial")):
        time.sleep(0.02)
    assert proc.poll() is None, "the writer finished before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not out.exists() and list(tmp_path.glob(".out.*.partial"))
    again = evoplan([*command(tmp_path, name), "--out", str(out)])
    assert again.returncode == 0, again.stderr
    assert not list(tmp_path.glob(".out.*.partial"))
    assert (out / ("simulation.json" if name == "simulate" else "summary.json")).is_file()


def test_a_study_killed_mid_way_resumes_to_the_uninterrupted_numbers(tmp_path):
    """SIGKILL while cells are being written; running the same command again finishes the
    study with the numbers of one never interrupted (a study folder is resumable by design)."""
    path = tmp_path / "s.yaml"
    path.write_text(STUDY.replace("seeds: 2", "seeds: 6"))
    assert evoplan(["study", str(path), "--out", str(tmp_path / "fresh")]).returncode == 0
    out = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "evoplan", "study", str(path), "--out", str(out)], env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while time.time() < deadline and len(list((out / "cells").glob("*.json"))) < 2:
        time.sleep(0.01)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not (out / "report.md").exists(), "killed after it finished: the test proves nothing"
    assert evoplan(["study", str(path), "--out", str(out)]).returncode == 0
    import pandas as pd
    got, expected = (pd.read_csv(d / "runs.csv").drop(columns="wall_seconds") for d in (out, tmp_path / "fresh"))
    pd.testing.assert_frame_equal(got, expected)
