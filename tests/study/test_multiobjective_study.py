"""Studies take the multi-objective adapters: each run reports its final hypervolume, the same on
every backend."""

from __future__ import annotations

import numpy as np
import pandas as pd

from evoplan.study.config import load_study
from evoplan.study.runner import run_study

STUDY = """
seed: 3
seeds: 2
budget: {evaluations: 24}
problems:
  - name: toolpath
    label: fountas_mo
    params:
      objectives: [machining_error, machining_time]
      weights: {machining_error: 0.5, machining_time: 0.5}
      normalization: {machining_error: [0.0, 0.2], machining_time: [0.0, 10.0]}
algorithms:
  - {name: nsga2, pop_size: 8, ref_point: [3.0, 3.0]}
output: {plots: false}
"""


def test_a_multi_objective_study_reports_hypervolumes_equal_on_serial_and_processes(tmp_path):
    path = tmp_path / "mo.yaml"
    path.write_text(STUDY)
    study = load_study(path)
    frames = {}
    for backend in ("serial", "processes"):
        run_study(study, str(path), tmp_path / backend, backend, workers=2, progress=False)
        frames[backend] = pd.read_csv(tmp_path / backend / "runs.csv").drop(columns=["wall_seconds"])
    runs = frames["serial"]
    assert (runs["status"] == "ok").all(), runs["error"].tolist()
    hv = runs["hypervolume"].to_numpy()
    assert np.isfinite(hv).all() and (hv > 0).all() and (hv <= 9.0).all()  # inside the reference box
    pd.testing.assert_frame_equal(frames["processes"], runs)
