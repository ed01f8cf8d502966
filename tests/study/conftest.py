"""Shared pieces of the study tests: a small study, and a repository root on workers' path."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

SMALL = """
seed: 11
seeds: 2
budget: {evaluations: 120}
problems:
  - {name: kubota, bits: 12}
  - {name: rastrigin, dimensions: [3], bits: 12}
algorithms:
  - {name: ga, population: 10}
  - {name: vega, population: 10, virus: {count: 3}}
  - {name: pymoo_de, pop_size: 10}
  - {name: deap_easimple, population: 10, representation: real}
output: {plots: false}
"""


@pytest.fixture(autouse=True)
def _workers_import_the_repository(monkeypatch):
    """Worker processes (forkserver, Dask) import ``tests.*`` problems from the repository root."""
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    monkeypatch.setenv("MPLBACKEND", "Agg")


@pytest.fixture
def small_study(tmp_path) -> Path:
    path = tmp_path / "small.yaml"
    path.write_text(SMALL)
    return path
