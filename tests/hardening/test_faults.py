"""Faults: workers that die or hang, user code that exits, runs killed at random points or racing
into one folder, a damaged checkpoint, a full disk, and workers outliving their parent."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import psutil
import pytest

from evoplan.cli import main
from evoplan.evaluation import Evaluator
from evoplan.parallel import ParallelEvaluator, open_pool

from .objectives import Dies, Exits, Hangs

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
X = np.array([[x, 0.1] for x in np.linspace(-0.9, 0.9, 8)])


def evoplan(*args, wait=True, **kw):
    cmd = [sys.executable, "-m", "evoplan", *map(str, args)]
    if not wait:
        return subprocess.Popen(cmd, env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return subprocess.run(cmd, capture_output=True, text=True, env=ENV, timeout=120, **kw)


def run_file(tmp_path, problem: str, generations: int = 6, extra: str = "", name: str = "r") -> Path:
    path = tmp_path / f"{name}.yaml"
    path.write_text(f"seed: 5\nproblem: {{name: '{problem}', bits: 10}}\n"
                    f"algorithm: {{name: vega, population: 6, virus: {{count: 2, max_length: 6}}}}\n"
                    f"termination: {{generations: {generations}}}\ncheckpoint: {{every_generations: 1}}\n"
                    f"output: {{plot: false}}\n{extra}")
    return path


def comparable(out: Path):
    history = pd.read_csv(out / "history.csv").drop(columns="seconds")
    best = json.loads((out / "best.json").read_text())
    best.pop("wall_seconds")
    return history, best


@pytest.fixture(scope="module")
def processes():
    pool = open_pool("processes", 2)
    yield pool
    pool.close()


def test_a_dying_worker_fails_its_rows_and_the_pool_is_rebuilt(processes):
    evaluator = ParallelEvaluator(Evaluator(Dies(threshold=0.5)), processes, chunks=len(X))
    result = evaluator(X)
    assert np.array_equal(result.failed, X[:, 0] > 0.5)
    assert np.allclose(result.f[~result.failed], (X[~result.failed] ** 2).sum(axis=1))
    assert any("died" in m for m in result.errors)
    assert processes.rebuilds >= 1
    again = evaluator(X[X[:, 0] <= 0.5])  # the rebuilt pool evaluates as before
    assert not again.failed.any()


def test_a_hanging_evaluation_times_out_and_the_pool_goes_on(processes):
    processes.timeout = 0.5
    try:
        evaluator = ParallelEvaluator(Evaluator(Hangs(threshold=0.5)), processes)
        t0 = time.perf_counter()
        result = evaluator(X)
        assert time.perf_counter() - t0 < 20
        assert result.failed[X[:, 0] > 0.5].all() and any("timeout_s" in m for m in result.errors)
        assert not evaluator(X[X[:, 0] <= 0.5]).failed.any()
    finally:
        processes.timeout = None


def test_sys_exit_in_the_objective_is_a_failure_not_the_end():
    result = Evaluator(Exits(threshold=0.5))(X)
    assert np.array_equal(result.failed, X[:, 0] > 0.5)
    assert any("SystemExit" in m for m in result.errors)


@pytest.mark.parametrize("backend", ["serial", "processes"])
def test_a_wrong_objective_shape_stops_at_the_first_batch(tmp_path, capsys, backend):
    extra = "" if backend == "serial" else "evaluation: {backend: processes, workers: 2}\n"
    path = run_file(tmp_path, "tests.hardening.objectives:WrongShape", extra=extra)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "expected shape (" in err and "provided (" in err
    assert not out.exists()


def _checkpoint_stamp(folder: Path):
    try:
        return (folder / "checkpoint.npz").stat().st_mtime_ns
    except FileNotFoundError:
        return None


def test_kills_at_random_points_resume_to_the_uninterrupted_result(tmp_path):
    """SIGKILL at random points (the first one before any checkpoint exists), then finish.

    Each later kill waits until that process has written a checkpoint of its own, then a random
    part of a generation more: every kill lands mid-run however slow or fast the host is."""
    cfg = run_file(tmp_path, "tests.hardening.objectives:Slow", generations=40, name="slow")
    cfg.write_text(cfg.read_text().replace("bits: 10}", "bits: 10, params: {delay: 0.05}}"))
    fresh = evoplan("run", cfg, "--out", tmp_path / "fresh", "--quiet")
    assert fresh.returncode == 0, fresh.stderr
    killed = tmp_path / "killed"
    rng = np.random.default_rng(14)
    kills = 0
    # the second kill lands as soon as the first checkpoint exists (VEGA's, at generation -1)
    for i, extra in enumerate([0.0, 0.0, *rng.uniform(0.0, 0.1, 2)]):
        before = _checkpoint_stamp(killed)
        resume = before is not None
        proc = evoplan("run", cfg, *(["--resume", killed] if resume else ["--out", killed]), "--quiet", wait=False)
        if i == 0:
            time.sleep(0.3)  # still importing: no checkpoint yet
        else:
            deadline = time.monotonic() + 60
            while _checkpoint_stamp(killed) == before and proc.poll() is None and time.monotonic() < deadline:
                time.sleep(0.01)
            time.sleep(extra)
        proc.send_signal(signal.SIGKILL)
        kills += proc.wait() == -signal.SIGKILL
    resume = (killed / "checkpoint.npz").exists()
    last = evoplan("run", cfg, *(["--resume", killed] if resume else ["--out", killed]), "--quiet")
    assert last.returncode == 0, last.stderr
    h1, b1 = comparable(killed)
    h2, b2 = comparable(tmp_path / "fresh")
    pd.testing.assert_frame_equal(h1, h2)
    assert b1 == b2
    assert kills == 4
    assert not list(killed.glob(".*.tmp"))


def test_two_runs_racing_into_one_folder_one_refuses(tmp_path):
    cfg = run_file(tmp_path, "tests.hardening.objectives:Slow", generations=3)
    cfg.write_text(cfg.read_text().replace("bits: 10}", "bits: 10, params: {delay: 0.2}}"))
    out = tmp_path / "out"
    procs = [evoplan("run", cfg, "--out", out, "--quiet", wait=False) for _ in range(2)]
    results = [(p.wait(timeout=120), p.stderr.read()) for p in procs]
    codes = sorted(code for code, _ in results)
    assert codes == [0, 2], results
    err = next(e for code, e in results if code == 2)
    assert "another evoplan run" in err or "not empty" in err


def test_a_damaged_checkpoint_is_refused(tmp_path):
    cfg = run_file(tmp_path, "kubota", generations=3)
    out = tmp_path / "out"
    assert evoplan("run", cfg, "--out", out, "--quiet").returncode == 0
    data = bytearray((out / "checkpoint.npz").read_bytes())
    data[len(data) // 2] ^= 0x10  # one flipped bit
    (out / "checkpoint.npz").write_bytes(bytes(data))
    proc = evoplan("run", cfg, "--resume", out)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert "cannot resume" in proc.stderr


def test_results_files_follow_the_umask(tmp_path):
    cfg = run_file(tmp_path, "kubota", generations=2)
    out = tmp_path / "out"
    assert evoplan("run", cfg, "--out", out, "--quiet", preexec_fn=lambda: os.umask(0o022)).returncode == 0
    assert {oct(p.stat().st_mode & 0o777) for p in out.iterdir()} == {"0o644"}


@pytest.mark.parametrize("how", [signal.SIGTERM, signal.SIGKILL])
def test_workers_end_with_their_parent(tmp_path, how):
    cfg = run_file(tmp_path, "tests.hardening.objectives:Slow", generations=200,
                   extra="evaluation: {backend: processes, workers: 2}\n")
    cfg.write_text(cfg.read_text().replace("bits: 10}", "bits: 10, params: {delay: 0.05}}"))
    proc = evoplan("run", cfg, "--out", tmp_path / "out", "--quiet", wait=False)
    parent = psutil.Process(proc.pid)
    deadline = time.time() + 30
    children: list[psutil.Process] = []
    while time.time() < deadline and len(children) < 3:  # fork server + 2 workers
        children = parent.children(recursive=True)
        time.sleep(0.2)
    assert len(children) >= 3, "the workers did not start"
    proc.send_signal(how)
    proc.wait(timeout=30)
    gone, alive = psutil.wait_procs(children, timeout=10)
    assert not alive, [p.pid for p in alive]
    if how == signal.SIGTERM:
        assert proc.returncode == 130


def test_a_full_disk_is_one_line_and_the_run_resumes(tmp_path):
    """On a tmpfs too small for the results: one line, no temp file, the checkpoint kept; resumed
    once there is room, the run ends with the numbers of an uninterrupted one."""
    small = tmp_path / "small"
    small.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=40k", "tmpfs", str(small)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip("mounting a small tmpfs needs privileges this machine does not give")
    try:
        cfg = run_file(tmp_path, "kubota", generations=3)
        cfg.write_text(cfg.read_text().replace("output: {plot: false}", "output: {plot: true}"))
        out = small / "out"
        proc = evoplan("run", cfg, "--out", out, "--quiet")
        assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
        assert "No space left" in proc.stderr
        assert not list(out.glob(".*.tmp")) and (out / "checkpoint.npz").is_file()
        assert not (out / "best.json").exists()
        subprocess.run(["mount", "-o", "remount,size=8m", str(small)], check=True)
        resumed = evoplan("run", cfg, "--resume", out, "--quiet")
        assert resumed.returncode == 0, resumed.stderr
        assert evoplan("run", cfg, "--out", tmp_path / "fresh", "--quiet").returncode == 0
        h1, b1 = comparable(out)
        h2, b2 = comparable(tmp_path / "fresh")
        pd.testing.assert_frame_equal(h1, h2)
        assert b1 == b2 and (out / "convergence.png").is_file()
    finally:
        subprocess.run(["umount", str(small)], capture_output=True)
