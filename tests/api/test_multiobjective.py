"""Multi-objective runs: NSGA-II on the two-objective toolpath problem, pareto.csv/png, hypervolume."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
import yaml

from evoplan.cli import main
from evoplan.multiobjective import hypervolume, nondominated

RUN = {
    "seed": 2,
    "problem": {"name": "toolpath", "params": {
        "objectives": ["machining_error", "machining_time"],
        "weights": {"machining_error": 0.5, "machining_time": 0.5},
        "normalization": {"machining_error": [0.0, 0.2], "machining_time": [0.0, 10.0]}}},
    "algorithm": {"name": "nsga2", "pop_size": 12},
    "termination": {"generations": 6},
}


def _run(tmp_path, run=RUN, name="run"):
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(run))
    return main(["run", str(path), "--out", str(tmp_path / name), "--quiet"]), tmp_path / name


def test_nsga2_writes_a_mutually_non_dominated_front(tmp_path, capsys):
    code, out = _run(tmp_path)
    assert code == 0
    front = pd.read_csv(out / "pareto.csv")
    assert len(front) >= 3
    raw = front[["machining_error", "machining_time"]].to_numpy()
    for i in range(len(raw)):  # no point is dominated by another one
        others = np.delete(raw, i, axis=0)
        dominated = (others <= raw[i]).all(axis=1) & (others < raw[i]).any(axis=1)
        assert not dominated.any(), f"row {i} is dominated"
    # the objective columns are the raw criteria normalized with the given bounds
    np.testing.assert_allclose(front["F_machining_error"], raw[:, 0] / 0.2, rtol=1e-9)
    np.testing.assert_allclose(front["F_machining_time"], raw[:, 1] / 10.0, rtol=1e-9)
    # variables are decoded: tool ids 1-9, every range kept
    assert front["tool"].between(1, 9).all() and front["stepover"].between(20, 45).all()
    # Eq. 9's choice: the lowest 0.5/0.5 weighted sum of the normalized objectives, once
    ws = 0.5 * front["F_machining_error"] + 0.5 * front["F_machining_time"]
    assert front["weighted_choice"].sum() == 1 and front["weighted_choice"].to_numpy()[np.argmin(ws)]
    history = pd.read_csv(out / "history.csv")
    hv = history["hypervolume"].to_numpy()
    assert len(hv) == 7 and (np.diff(hv) >= -1e-12).all() and hv[-1] > 0  # the archive only grows
    best = json.loads((out / "best.json").read_text())
    assert best["objective"] == pytest.approx(ws.min(), rel=1e-9)  # best = lowest weighted sum seen
    assert (out / "pareto.png").stat().st_size > 5000


def test_sms_emoa_and_nsga3_run(tmp_path):
    for name in ("sms_emoa", "nsga3"):
        run = {**RUN, "algorithm": {"name": name, "pop_size": 8, **({"partitions": 4} if name == "nsga3" else {})},
               "termination": {"generations": 3}, "output": {"plot": False}}
        code, out = _run(tmp_path, run, name)
        assert code == 0 and len(pd.read_csv(out / "pareto.csv")) >= 1


def test_single_objective_algorithm_on_two_objectives_is_refused(tmp_path, capsys):
    code, out = _run(tmp_path, {**RUN, "algorithm": {"name": "vega"}}, "vega")
    err = capsys.readouterr().err
    assert code == 2 and "algorithm.name: vega optimizes one objective" in err and "nsga2" in err
    assert not out.exists()


def test_indicator_helpers_against_hand_values():
    F = np.array([[1.0, 3.0], [2.0, 2.0], [3.0, 1.0], [3.0, 3.0], [np.inf, 0.0]])
    assert nondominated(F).tolist() == [True, True, True, False, False]
    # three unit steps below (4, 4): 3 + 2 + 1 unit squares
    assert hypervolume(F, np.array([4.0, 4.0])) == pytest.approx(6.0)


def test_a_resumed_multi_objective_run_continues_exactly():
    import pickle

    from evoplan.api import run_config
    from evoplan.engine import Termination, run
    from evoplan.multiobjective import connect
    from evoplan.runner import prepare

    cfg, _ = run_config(RUN, "sms_emoa", pop_size=8, termination=5, seed=3)

    def fresh():
        prepared = prepare(cfg)
        state = prepared.new_state()
        connect(prepared.evaluator, state.algorithm, prepared.search.decode)
        return prepared, state

    p, whole = fresh()
    run(whole, p.search, p.evaluator, Termination(generations=5))
    p, half = fresh()
    run(half, p.search, p.evaluator, Termination(generations=2))
    p2, resumed = prepare(cfg), pickle.loads(pickle.dumps(half))  # what a checkpoint holds
    connect(p2.evaluator, resumed.algorithm, p2.search.decode)
    run(resumed, p2.search, p2.evaluator, Termination(generations=5))
    assert resumed.best_f == whole.best_f and resumed.evaluations == whole.evaluations
    np.testing.assert_array_equal(resumed.algorithm.front_F, whole.algorithm.front_F)
    assert resumed.algorithm.hypervolumes == whole.algorithm.hypervolumes


@pytest.mark.parametrize("backend", ["processes", "dask"])
def test_a_multi_objective_run_on_workers_gives_the_serial_front(tmp_path, backend):
    run = {**RUN, "termination": {"generations": 3}}
    code, serial = _run(tmp_path, run, "serial")
    assert code == 0
    code, parallel = _run(tmp_path, {**run, "evaluation": {"backend": backend, "workers": 2}}, backend)
    assert code == 0
    a, b = pd.read_csv(serial / "pareto.csv"), pd.read_csv(parallel / "pareto.csv")
    assert len(a) >= 2
    pd.testing.assert_frame_equal(a, b)
    drop = ["seconds"]
    pd.testing.assert_frame_equal(pd.read_csv(serial / "history.csv").drop(columns=drop),
                                  pd.read_csv(parallel / "history.csv").drop(columns=drop))
