"""A dying or hanging row costs that row, not the batch: processes and Dask pools (the rows of
``workers.X`` past 0.5 die or hang; the others keep their sphere values)."""

from __future__ import annotations

import time

import pytest

from evoplan.evaluation import Evaluator
from evoplan.parallel import ParallelEvaluator, open_pool

from .objectives import Dies, Hangs
from .workers import X, check_rows


@pytest.mark.parametrize("chunks", [2, 3])
def test_processes_a_dying_row_fails_alone_in_a_chunk_of_many(chunks):
    pool = open_pool("processes", 2)
    try:
        check_rows(ParallelEvaluator(Evaluator(Dies()), pool, chunks=chunks)(X))
        assert pool.rebuilds >= 1
    finally:
        pool.close()


def test_processes_a_hanging_row_fails_alone_and_healthy_rows_never_time_out():
    pool = open_pool("processes", 2, timeout=0.5)
    try:
        t0 = time.perf_counter()
        check_rows(ParallelEvaluator(Evaluator(Hangs()), pool, chunks=2)(X))
        assert time.perf_counter() - t0 < 30
    finally:
        pool.close()


def test_dask_a_dying_and_a_hanging_row_fail_alone():
    pool = open_pool("dask", 2, timeout=0.5)
    try:
        check_rows(ParallelEvaluator(Evaluator(Hangs()), pool, chunks=2)(X))
        pool.timeout = None
        result = ParallelEvaluator(Evaluator(Dies()), pool, chunks=2)(X)
        check_rows(result)
        assert any("died" in m for m in result.errors), result.errors
    finally:
        pool.close()


def test_dask_close_survives_a_nanny_still_starting_a_worker(monkeypatch):
    """distributed's close fails ("can only join a started process") when a nanny is still
    starting the worker that replaces a killed one; the pool tries again and does not raise."""
    pool = open_pool("dask", 1)
    real, calls = pool.cluster.close, []

    def racing_close(*args, **kwargs):
        calls.append(1)
        if len(calls) == 1:
            raise AssertionError("can only join a started process")
        return real(*args, **kwargs)

    monkeypatch.setattr(pool.cluster, "close", racing_close)
    pool.close()
    assert len(calls) == 2
    assert pool.cluster.status.name == "closed"


class _ClosingExecutor:
    """An executor whose worker died during the wave: the next submit, which would start a
    process on its closed queue, fails as CPython's does (``OSError: handle is closed``)."""

    def __init__(self, real):
        self.real, self.calls = real, 0

    def submit(self, fn, *args):
        self.calls += 1
        if self.calls > 1:
            raise OSError("handle is closed")
        return self.real.submit(fn, *args)

    def __getattr__(self, name):
        return getattr(self.real, name)


def test_processes_a_worker_dying_while_its_wave_is_submitted_costs_only_its_rows():
    pool = open_pool("processes", 2)
    try:
        pool.executor = _ClosingExecutor(pool.executor)
        check_rows(ParallelEvaluator(Evaluator(Dies()), pool, chunks=2)(X))
        assert pool.rebuilds >= 1
    finally:
        pool.close()
