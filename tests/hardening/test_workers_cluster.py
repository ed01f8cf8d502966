"""A real Dask cluster (``dask scheduler`` and two ``dask worker`` processes) loses a worker
mid-study: the study ends with the numbers of a serial one."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pandas as pd

from evoplan.cli import main

from .workers import ENV, OBJ, free_port, runs_table


def test_a_real_dask_cluster_loses_a_worker_mid_study(tmp_path):
    """``dask scheduler`` + two ``dask worker`` processes on 127.0.0.1; one is killed mid-study."""
    port = free_port()
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
        pd.testing.assert_frame_equal(runs_table(tmp_path / "dask"), runs_table(tmp_path / "ref"))
    finally:
        for p in reversed(procs):
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait(timeout=10)
