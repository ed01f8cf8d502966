"""Shared pieces of the worker-fault tests (``test_workers_*.py``): the sphere rows of which
some misbehave, the run and study files, and how their results are read back.

The tests are split by what they start (rows, runs, studies, a real cluster) so that the
test workers (pytest-xdist, one file per worker) run them side by side."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
X = np.array([[x, 0.1] for x in np.linspace(-0.9, 0.9, 8)])
BAD = X[:, 0] > 0.5
OBJ = "tests.hardening.objectives"


def evoplan(*args, timeout=240):
    return subprocess.run([sys.executable, "-m", "evoplan", *map(str, args)], capture_output=True, text=True,
                          env=ENV, timeout=timeout)


def check_rows(result):
    """Only the misbehaving rows failed; the others have their sphere values."""
    assert np.array_equal(result.failed, BAD), result.errors
    assert np.allclose(result.f[~BAD], (X[~BAD] ** 2).sum(axis=1))


def run_file(tmp_path, problem, name, extra=""):
    path = tmp_path / f"{name}.yaml"
    path.write_text(f"seed: 5\nproblem: {{name: '{OBJ}:{problem}', bits: 10}}\n"
                    "algorithm: {name: vega, population: 8, virus: {count: 2, max_length: 6}}\n"
                    f"termination: {{generations: 4}}\noutput: {{plot: false}}\n{extra}")
    return path


def results(out: Path):
    history = pd.read_csv(out / "history.csv").drop(columns="seconds")
    best = json.loads((out / "best.json").read_text())
    for k in ("wall_seconds", "problem", "failure_messages"):
        best.pop(k)
    return history, best


def study_file(tmp_path, problem, name, extra=""):
    path = tmp_path / f"{name}.yaml"
    path.write_text("seed: 3\nseeds: 3\nbudget: {evaluations: 60}\n"
                    f"problems:\n  - {{name: kubota}}\n  - {{name: '{OBJ}:{problem}', label: p, params: {{threshold: 0.9}}}}\n"
                    f"algorithms:\n  - {{name: ga, population: 6}}\noutput: {{plots: false, ioh: false}}\n{extra}")
    return path


def runs_table(out: Path) -> pd.DataFrame:
    runs = pd.read_csv(out / "runs.csv").set_index("key")
    return runs.drop(columns=["wall_seconds", "failure_messages"])


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]
