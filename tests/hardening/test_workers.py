"""A dying or hanging worker costs its evaluation (its row, or in a study its cell), not the run:
on processes and Dask, in runs and studies, with the numbers of a run whose same rows fail
cleanly (``Fails`` returns NaN where ``Dies`` exits and ``Hangs`` sleeps)."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from evoplan.cli import main
from evoplan.evaluation import Evaluator
from evoplan.parallel import ParallelEvaluator, open_pool

from .objectives import Dies, Hangs

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
X = np.array([[x, 0.1] for x in np.linspace(-0.9, 0.9, 8)])
BAD = X[:, 0] > 0.5
OBJ = "tests.hardening.objectives"


def evoplan(*args, timeout=240):
    return subprocess.run([sys.executable, "-m", "evoplan", *map(str, args)], capture_output=True, text=True,
                          env=ENV, timeout=timeout)


def _check_rows(result):
    """Only the misbehaving rows failed; the others have their sphere values."""
    assert np.array_equal(result.failed, BAD), result.errors
    assert np.allclose(result.f[~BAD], (X[~BAD] ** 2).sum(axis=1))


@pytest.mark.parametrize("chunks", [2, 3])
def test_processes_a_dying_row_fails_alone_in_a_chunk_of_many(chunks):
    pool = open_pool("processes", 2)
    try:
        _check_rows(ParallelEvaluator(Evaluator(Dies()), pool, chunks=chunks)(X))
        assert pool.rebuilds >= 1
    finally:
        pool.close()


def test_processes_a_hanging_row_fails_alone_and_healthy_rows_never_time_out():
    pool = open_pool("processes", 2, timeout=0.5)
    try:
        t0 = time.perf_counter()
        _check_rows(ParallelEvaluator(Evaluator(Hangs()), pool, chunks=2)(X))
        assert time.perf_counter() - t0 < 30
    finally:
        pool.close()


def test_dask_a_dying_and_a_hanging_row_fail_alone():
    pool = open_pool("dask", 2, timeout=0.5)
    try:
        _check_rows(ParallelEvaluator(Evaluator(Hangs()), pool, chunks=2)(X))
        pool.timeout = None
        result = ParallelEvaluator(Evaluator(Dies()), pool, chunks=2)(X)
        _check_rows(result)
        assert any("died" in m for m in result.errors), result.errors
    finally:
        pool.close()


def _run_file(tmp_path, problem, name, extra=""):
    path = tmp_path / f"{name}.yaml"
    path.write_text(f"seed: 5\nproblem: {{name: '{OBJ}:{problem}', bits: 10}}\n"
                    "algorithm: {name: vega, population: 8, virus: {count: 2, max_length: 6}}\n"
                    f"termination: {{generations: 4}}\noutput: {{plot: false}}\n{extra}")
    return path


def _results(out: Path):
    history = pd.read_csv(out / "history.csv").drop(columns="seconds")
    best = json.loads((out / "best.json").read_text())
    for k in ("wall_seconds", "problem", "failure_messages"):
        best.pop(k)
    return history, best


@pytest.mark.parametrize("backend,problem,timeout", [("processes", "Dies", None), ("processes", "Hangs", 0.5),
                                                     ("dask", "Dies", None)])
def test_a_run_goes_on_with_the_numbers_of_clean_failures(tmp_path, clean_run, backend, problem, timeout):
    extra = f"evaluation: {{backend: {backend}, workers: 2" + (f", timeout_s: {timeout}" if timeout else "") + "}\n"
    cfg = _run_file(tmp_path, problem, "bad", extra)
    proc = evoplan("run", cfg, "--out", tmp_path / "bad", "--quiet")
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    h1, b1 = _results(tmp_path / "bad")
    h2, b2 = _results(clean_run)
    pd.testing.assert_frame_equal(h1, h2)
    assert b1 == b2 and b1["failures"] > 0


@pytest.fixture(scope="module")
def clean_run(tmp_path_factory):
    """The reference run whose bad rows fail cleanly (NaN), shared by the run tests (in-process:
    nothing misbehaves in it)."""
    root = tmp_path_factory.mktemp("clean_run")
    assert main(["run", str(_run_file(root, "Fails", "ref")), "--out", str(root / "ref"), "--quiet"]) == 0
    return root / "ref"


@pytest.fixture(scope="module")
def clean_study(tmp_path_factory):
    """The reference study whose bad rows fail cleanly, shared by the study tests."""
    root = tmp_path_factory.mktemp("clean_study")
    assert main(["study", str(_study(root, "Fails", "ref")), "--out", str(root / "ref"), "--quiet"]) == 0
    return _runs(root / "ref")


def _study(tmp_path, problem, name, extra=""):
    path = tmp_path / f"{name}.yaml"
    path.write_text("seed: 3\nseeds: 3\nbudget: {evaluations: 60}\n"
                    f"problems:\n  - {{name: kubota}}\n  - {{name: '{OBJ}:{problem}', label: p, params: {{threshold: 0.9}}}}\n"
                    f"algorithms:\n  - {{name: ga, population: 6}}\noutput: {{plots: false, ioh: false}}\n{extra}")
    return path


def _runs(out: Path) -> pd.DataFrame:
    runs = pd.read_csv(out / "runs.csv").set_index("key")
    return runs.drop(columns=["wall_seconds", "failure_messages"])


def test_a_study_cell_whose_worker_dies_fails_alone_and_reproducibly(tmp_path, clean_study):
    cfg = _study(tmp_path, "Dies", "dies")
    runs = []
    for backend in ("processes", "processes", "dask"):
        out = tmp_path / f"dies-{len(runs)}"
        proc = evoplan("study", cfg, "--out", out, "--backend", backend, "--workers", 2)
        assert "Traceback" not in proc.stderr, proc.stderr
        runs.append(_runs(out))
    expected = clean_study
    for r in runs:
        pd.testing.assert_frame_equal(r, runs[0])
    died = runs[0].status != "ok"
    assert died.sum() >= 1 and runs[0].index[died].str.startswith("p.").all()
    assert (runs[0].error[died].str.contains("worker died")).all()
    # every cell whose worker did not die has the numbers of the clean study
    ok = runs[0].index[~died]
    pd.testing.assert_frame_equal(runs[0].loc[ok].drop(columns="error"), expected.loc[ok].drop(columns="error"),
                                  check_dtype=False)


@pytest.mark.parametrize("backend", ["processes", "dask"])
def test_a_study_bounds_a_hanging_evaluation_with_timeout_s(tmp_path, clean_study, backend):
    cfg = _study(tmp_path, "Hangs", "hangs", "evaluation: {timeout_s: 0.3}\n")
    proc = evoplan("study", cfg, "--out", tmp_path / "hangs", "--backend", backend, "--workers", 2)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    got, expected = _runs(tmp_path / "hangs"), clean_study
    assert (got.status == "ok").all() and got.failures.sum() > 0
    pd.testing.assert_frame_equal(got, expected)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_real_dask_cluster_loses_a_worker_mid_study(tmp_path):
    """``dask scheduler`` + two ``dask worker`` processes on 127.0.0.1; one is killed mid-study."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    dask = [sys.executable, "-m", "dask"]  # the `dask` command, run by this interpreter
    procs = [subprocess.Popen([*dask, "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--dashboard-address", ":0", "--no-show"], env=ENV,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)]
    try:
        for _ in range(2):
            procs.append(subprocess.Popen([*dask, "worker", address, "--nthreads", "1", "--no-nanny",
                                           "--host", "127.0.0.1", "--dashboard-address", ":0"], env=ENV,
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True))
        cfg = tmp_path / "slow.yaml"
        cfg.write_text("seed: 3\nseeds: 6\nbudget: {evaluations: 40}\n"
                       f"problems:\n  - {{name: '{OBJ}:Slow', label: p, params: {{delay: 0.05}}}}\n"
                       "algorithms:\n  - {name: ga, population: 6}\noutput: {plots: false, ioh: false}\n")
        assert main(["study", str(cfg), "--out", str(tmp_path / "ref"), "--quiet"]) == 0
        study = subprocess.Popen([sys.executable, "-m", "evoplan", "study", cfg, "--out", tmp_path / "dask",
                                  "--backend", "dask", "--scheduler", address], env=ENV,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        cells = tmp_path / "dask" / "cells"
        deadline = time.time() + 90
        while time.time() < deadline and not (cells.is_dir() and any(cells.iterdir())):
            time.sleep(0.1)  # kill once the study is under way
        os.killpg(procs[2].pid, signal.SIGKILL)
        out, err = study.communicate(timeout=180)
        assert study.returncode == 0 and "Traceback" not in err, err
        pd.testing.assert_frame_equal(_runs(tmp_path / "dask"), _runs(tmp_path / "ref"))
    finally:
        for p in reversed(procs):
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait(timeout=10)
