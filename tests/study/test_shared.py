"""Studies share what their runs share: one toolpath problem (layouts memoized) per worker,
the same numbers as problems built afresh for every run, on every backend."""

from __future__ import annotations

import pandas as pd
import pytest

from evoplan.study import shared
from evoplan.study.config import load_study
from evoplan.study.runner import run_study

TOOLPATH = """
seed: 4
seeds: 2
budget: {evaluations: 14}
cache: {budget: distinct}
problems:
  - name: toolpath
    label: choi_small
    params:
      surface: choi
      tools: [{id: 1, type: ball, diameter: 6.35}]
      machine: 3axis
      spacing: stepover
      h_c: 0.254
      delta_l: 40
      feed_angle: optimized
      zoning: {method: kmeans, mesh: [14, 14]}
      ranges: {stepover: [30, 60], step: [2, 4], zones: [1, 2]}
      weights: {eq4_total: 0.5, scallop_max: 0.5}
      normalization: {eq4_total: [1000, 4800], scallop_max: [0, 1]}
algorithms:
  - {name: ga, population: 6}
  - {name: vega, population: 6, virus: {count: 2, max_length: 4}}
output: {plots: false}
"""


def results(out):
    runs = pd.read_csv(out / "runs.csv").drop(columns=["wall_seconds"])
    histories = pd.concat([pd.read_csv(out / "histories" / f"{k}.csv").assign(key=k) for k in runs["key"]])
    return runs, histories.drop(columns=["seconds"])


@pytest.fixture
def toolpath_study(tmp_path):
    path = tmp_path / "choi_small.yaml"
    path.write_text(TOOLPATH)
    return path


def test_a_shared_problem_gives_the_numbers_of_fresh_ones_on_every_backend(toolpath_study, tmp_path, monkeypatch):
    study = load_study(toolpath_study)
    shared.clear()
    run_study(study, str(toolpath_study), tmp_path / "serial", "serial", progress=False)
    assert shared.STATS == {"built": 1, "reused": 3}  # one build, reused by the three other runs
    reference = results(tmp_path / "serial")
    assert (reference[0]["status"] == "ok").all()
    monkeypatch.setattr(shared, "SHARED", frozenset())  # every run builds its own problem
    shared.clear()
    run_study(study, str(toolpath_study), tmp_path / "fresh", "serial", progress=False)
    assert shared.STATS == {"built": 0, "reused": 0}
    monkeypatch.undo()
    for out in ("fresh",):
        runs, hist = results(tmp_path / out)
        pd.testing.assert_frame_equal(runs, reference[0])
        pd.testing.assert_frame_equal(hist, reference[1])
    for backend in ("processes", "dask"):
        run_study(study, str(toolpath_study), tmp_path / backend, backend, workers=2, progress=False)
        runs, hist = results(tmp_path / backend)
        pd.testing.assert_frame_equal(runs, reference[0])
        pd.testing.assert_frame_equal(hist, reference[1])


def test_only_listed_problems_are_shared_and_the_memo_is_bounded(monkeypatch):
    shared.clear()
    assert shared.problem_for("kubota", {}) is None and shared.STATS["built"] == 0
    monkeypatch.setattr(shared, "SHARED", frozenset({"kubota", "rastrigin"}))
    monkeypatch.setattr(shared, "MAX_KEPT", 2)
    a = shared.problem_for("kubota", {})
    assert shared.problem_for("kubota", {}) is a and shared.STATS == {"built": 1, "reused": 1}
    b = shared.problem_for("rastrigin", {"n_var": 3})
    assert b is not shared.problem_for("rastrigin", {"n_var": 4})  # another configuration, another key
    assert shared.problem_for("kubota", {}) is not a  # dropped: the memo keeps the two most recent
    assert shared.config_key("k", {"a": 1, "b": 2}) == shared.config_key("k", {"b": 2, "a": 1})
    shared.clear()
