"""Backends: the same study gives the same numbers serially, in processes and on Dask; one
population's evaluations spread over workers give the serial evaluator's numbers."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from evoplan.config import parse_config
from evoplan.engine import run
from evoplan.evaluation import Evaluation
from evoplan.parallel import ParallelEvaluator, SerialPool, open_pool
from evoplan.runner import prepare
from evoplan.study.config import load_study
from evoplan.study.runner import run_study


def results(out) -> tuple[pd.DataFrame, pd.DataFrame]:
    runs = pd.read_csv(out / "runs.csv").drop(columns=["wall_seconds"])
    histories = pd.concat([pd.read_csv(out / "histories" / f"{k}.csv").assign(key=k) for k in runs["key"]])
    return runs, histories.drop(columns=["seconds"])


def test_serial_processes_and_dask_give_identical_numbers(small_study, tmp_path):
    study = load_study(small_study)
    outs = {}
    for backend in ("serial", "processes", "dask"):
        outs[backend] = tmp_path / backend
        execution = run_study(study, str(small_study), outs[backend], backend, workers=2, progress=False)
        assert execution["ran"] == 16 and execution["failed"] == 0
    serial_runs, serial_hist = results(outs["serial"])
    assert (serial_runs["status"] == "ok").all() and serial_runs["final_best"].notna().all()
    for backend in ("processes", "dask"):
        runs, hist = results(outs[backend])
        pd.testing.assert_frame_equal(runs, serial_runs)
        pd.testing.assert_frame_equal(hist, serial_hist)
    for name in ("summary.csv", "tests.csv"):
        a = pd.read_csv(outs["serial"] / name).drop(columns=["wall_seconds"], errors="ignore")
        b = pd.read_csv(outs["dask"] / name).drop(columns=["wall_seconds"], errors="ignore")
        pd.testing.assert_frame_equal(a, b)


@pytest.fixture(scope="module")
def dask_scheduler():
    """A local Dask cluster of 2 workers, reached through its address like a real cluster."""
    import logging

    from distributed import LocalCluster

    cluster = LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None,
                           scheduler_kwargs={"dashboard_address": ":0"}, silence_logs=logging.ERROR)
    yield cluster.scheduler_address
    cluster.close()


def sleepy_run(evaluator_for):
    cfg = parse_config({"seed": 2, "problem": {"name": "tests.study.blackboxes:Sleepy", "params": {"delay": 0.002}},
                        "algorithm": {"name": "ga", "population": 12}, "termination": {"generations": 3}})
    p = prepare(cfg)
    state = p.new_state()
    run(state, p.space, evaluator_for(p.evaluator), p.termination)
    return state


@pytest.mark.parametrize("backend", ["processes", "dask"])
def test_parallel_evaluation_gives_the_serial_numbers(backend, dask_scheduler):
    serial = sleepy_run(lambda ev: ev)
    pool = open_pool(backend, workers=2, scheduler=dask_scheduler if backend == "dask" else None)
    try:
        assert pool.workers == 2
        parallel = sleepy_run(lambda ev: ParallelEvaluator(ev, pool))
    finally:
        pool.close()
    assert [row[:-1] for row in parallel.history] == [row[:-1] for row in serial.history]  # but wall time
    assert parallel.best_f == serial.best_f and np.array_equal(parallel.best_g, serial.best_g)
    assert parallel.evaluations == serial.evaluations
    assert parallel.evaluations + parallel.cache_hits == 12 + 3 * 11  # every genotype asked for


def test_a_chunk_lost_to_the_backend_fails_only_its_row_at_fault():
    def evaluator(X):
        if (X[:, 0] > 10).any():
            raise ConnectionError("worker lost")
        return Evaluation(X[:, 0].astype(float), np.zeros(len(X), bool), [])

    X = np.array([[1.0], [2.0], [11.0], [3.0]])
    result = ParallelEvaluator(evaluator, SerialPool(), chunks=2)(X)
    assert result.f.tolist() == [1.0, 2.0, np.inf, 3.0]  # the lost chunk's rows, run again one by one
    assert result.failed.tolist() == [False, False, True, False]
    assert result.errors == ["evaluation backend serial: ConnectionError: worker lost"]
