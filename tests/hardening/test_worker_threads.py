"""The processes backend shares the cores out: each worker's BLAS pools get ``cores // workers``
threads, so that two workers on two cores do not run four spinning OpenBLAS threads; a local
Dask cluster's workers keep glibc's malloc thresholds."""

from __future__ import annotations

import os

import pytest
from threadpoolctl import threadpool_info

from evoplan.parallel import open_pool
from evoplan.process_pool import worker_threads


def _threads_seen() -> tuple[list[dict], str | None]:
    """In a worker: its thread pools, and the variable the libraries it loads later read."""
    return threadpool_info(), os.environ.get("OPENBLAS_NUM_THREADS")


def test_worker_threads_share_the_cores_out():
    cores = os.cpu_count() or 1
    assert worker_threads(1) == cores
    assert worker_threads(cores) == 1
    assert worker_threads(4 * cores) == 1  # never none


def test_each_worker_s_blas_pools_have_the_shared_out_threads():
    pool = open_pool("processes", 2)
    try:
        info, env = pool.submit(_threads_seen).result(timeout=60)
    finally:
        pool.close()
    blas = [lib for lib in info if lib["user_api"] == "blas"]
    assert blas, info  # numpy's OpenBLAS at least is loaded in a worker
    assert {lib["num_threads"] for lib in blas} == {worker_threads(2)}, blas
    assert env == str(worker_threads(2))


def _trim_threshold() -> str | None:
    return os.environ.get("MALLOC_TRIM_THRESHOLD_")


def test_local_dask_workers_keep_glibc_s_own_malloc_thresholds(monkeypatch):
    """distributed's nannies set MALLOC_TRIM_THRESHOLD_ before they spawn a worker, which fixes
    glibc's mmap threshold and made numpy-heavy batches 1.8x slower; evoplan's local cluster
    drops it (and keeps one BLAS thread a worker), also when an earlier cluster's nanny left it
    in this process's environment, which is given back afterwards."""
    pytest.importorskip("distributed")
    monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", "65536")  # as a default cluster's nanny leaves it
    pool = open_pool("dask", 2)
    try:
        seen = pool.client.run(_trim_threshold)
        env = pool.client.run(_threads_seen)
    finally:
        pool.close()
    assert len(seen) == 2 and set(seen.values()) == {None}, seen
    assert {e[1] for e in env.values()} == {"1"}, env
    assert os.environ["MALLOC_TRIM_THRESHOLD_"] == "65536"
