"""Worker pools (serial, local processes, Dask distributed) and parallel batch evaluation.

A :class:`Pool` runs functions somewhere else and gives back their results; the same small
interface for the three backends serves both parallel uses in evoplan:

- a study runs whole runs as tasks (``submit`` + ``as_completed``, see :mod:`evoplan.study`);
- :class:`ParallelEvaluator` spreads one population's evaluations over the workers (``bind`` an
  evaluator once, then ``call`` it on chunks of rows): the place for expensive black boxes.

Workers run one task at a time (Dask: one thread per worker) so that libraries drawing from a
process-global generator stay reproducible. Opening a pool checks it: an address where no Dask
scheduler answers, or a scheduler without workers, is a one-line :class:`EvoplanError`.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import pickle
import uuid
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures import as_completed as futures_completed
from typing import Any, Callable, Iterable, Iterator

import numpy as np

from .errors import EvoplanError
from .evaluation import Evaluation

SCHEDULER_TIMEOUT = 5.0  # seconds to reach a scheduler, and to see its first worker


class _Done:
    """The result of a task run in the calling process, computed when first asked for."""

    def __init__(self, fn: Callable, args: tuple) -> None:
        self.fn, self.args, self._value, self._error, self._ran = fn, args, None, None, False

    def result(self):
        if not self._ran:
            self._ran = True
            try:
                self._value = self.fn(*self.args)
            except Exception as e:  # noqa: BLE001 - re-raised to the caller, as a future does
                self._error = e
        if self._error is not None:
            raise self._error
        return self._value


class SerialPool:
    """Everything in the calling process, in order (the reference the others must match)."""

    name = "serial"

    def __init__(self, workers: int | None = None, scheduler: str | None = None) -> None:
        self.workers = 1

    def submit(self, fn: Callable, *args) -> _Done:
        return _Done(fn, args)

    def as_completed(self, futures: Iterable) -> Iterator:
        for f in futures:
            f.result()
            yield f

    def bind(self, obj: Callable) -> Any:
        return obj

    def call(self, handle: Any, chunks: list) -> list:
        return [_outcome(_Done(handle, (c,))) for c in chunks]

    def close(self) -> None:
        pass


def _outcome(future):
    """A task's result, or the exception it ended with (one chunk's loss is not the batch's)."""
    try:
        return future.result()
    except Exception as e:  # noqa: BLE001 - reported as failures of the chunk's rows
        return e


_BOUND: dict[str, Callable] = {}  # a worker process's bound callables, by token


def _call_blob(token: str, blob: bytes, arg):
    """Run a bound callable in a worker process, unpickling it on the worker's first call."""
    fn = _BOUND.get(token)
    if fn is None:
        _BOUND.clear()  # one bound evaluator at a time per worker
        fn = _BOUND[token] = pickle.loads(blob)
    return fn(arg)


class ProcessPool:
    """Local worker processes (``concurrent.futures``), started by a fork server."""

    name = "processes"

    def __init__(self, workers: int | None = None, scheduler: str | None = None) -> None:
        self.workers = workers or os.cpu_count() or 1
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(["evoplan.study.cell"])
        self.executor = ProcessPoolExecutor(max_workers=self.workers, mp_context=ctx)

    def submit(self, fn: Callable, *args):
        return self.executor.submit(fn, *args)

    def as_completed(self, futures: Iterable) -> Iterator:
        return futures_completed(list(futures))

    def bind(self, obj: Callable) -> tuple[str, bytes]:
        return uuid.uuid4().hex, pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)

    def call(self, handle: tuple[str, bytes], chunks: list) -> list:
        futures = [self.executor.submit(_call_blob, *handle, c) for c in chunks]
        return [_outcome(f) for f in futures]

    def close(self) -> None:
        self.executor.shutdown(wait=True, cancel_futures=True)


def _call(fn: Callable, arg):
    return fn(arg)


QUIET_WORKERS = {"distributed.worker.profile.enabled": False}


def worker_slots(client) -> int:
    """Tasks a Dask cluster runs at once: the threads of *all* its workers.

    Not ``len(client.scheduler_info()["workers"])``: distributed 2025.4 to 2026.6 truncate that
    dict to 5 workers by default, which cut a population into 5 chunks on 16 workers (4x
    instead of 10x in ``runs/bench/parallel_evaluation.py``).
    """
    return int(sum(client.nthreads().values()))


class DaskPool:
    """Dask distributed: a local cluster of ``workers`` processes, or the scheduler at an address."""

    name = "dask"

    def __init__(self, workers: int | None = None, scheduler: str | None = None, label: str = "--scheduler") -> None:
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise EvoplanError("the dask backend needs the distributed package: pip install \"evoplan[dask]\"") from None
        self.cluster = None
        if scheduler:
            try:
                self.client = Client(scheduler, timeout=f"{SCHEDULER_TIMEOUT}s", set_as_default=False)
            except (OSError, ValueError, TypeError) as e:
                raise EvoplanError(f"{label}: {scheduler}: no Dask scheduler answers ({str(e).splitlines()[0]})") from None
            try:
                self.client.wait_for_workers(1, timeout=SCHEDULER_TIMEOUT)
            except Exception:  # noqa: BLE001 - distributed raises TimeoutError variants
                self.client.close()
                raise EvoplanError(f"{label}: {scheduler}: the scheduler has no workers") from None
        else:
            import dask

            n = workers or os.cpu_count() or 1
            # no dashboard; the scheduler's HTTP endpoint on a free port (8787 may be taken); no
            # statistical profiler sampling every worker thread (CPU that n workers share)
            with dask.config.set(QUIET_WORKERS):
                self.cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                            dashboard_address=None, scheduler_kwargs={"dashboard_address": ":0"},
                                            silence_logs=logging.ERROR)
            self.client = Client(self.cluster, set_as_default=False)
        self.workers = worker_slots(self.client) or (workers or 1)

    def submit(self, fn: Callable, *args):
        return self.client.submit(fn, *args, pure=False)

    def as_completed(self, futures: Iterable) -> Iterator:
        from distributed import as_completed

        return as_completed(list(futures), loop=self.client.loop)

    def bind(self, obj: Callable):
        return self.client.scatter(obj, broadcast=True, hash=False)

    def call(self, handle, chunks: list) -> list:
        # one graph message out and one gather back (not a round trip per chunk)
        futures = self.client.map(_call, [handle] * len(chunks), chunks, pure=False)
        done = iter(self.client.gather(futures, errors="skip"))
        return [next(done) if f.status == "finished" else _outcome(f) for f in futures]

    def close(self) -> None:
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()


POOLS: dict[str, type] = {"serial": SerialPool, "processes": ProcessPool, "dask": DaskPool}


def open_pool(backend: str = "serial", workers: int | None = None, scheduler: str | None = None,
              label: str = "--scheduler", timeout: float | None = None):
    """A pool by backend name; bad combinations and unreachable schedulers are one-line errors.

    ``label`` names the setting in those errors (``--scheduler`` on the command line, ``FILE:
    evaluation.scheduler`` for a run file); ``timeout``: seconds a task may run (processes, dask).
    """
    if backend not in POOLS:
        raise EvoplanError(f"unknown backend {backend!r} (known: {', '.join(POOLS)})")
    if scheduler and backend != "dask":
        raise EvoplanError(f"{label} is for --backend dask, not {backend}")
    if workers is not None and workers < 1:
        raise EvoplanError(f"--workers must be at least 1, got {workers}")
    pool = POOLS[backend](workers, scheduler, label) if backend == "dask" else POOLS[backend](workers, scheduler)
    pool.timeout = timeout
    return pool


class ParallelEvaluator:
    """``X: (n, d) -> Evaluation`` like :class:`~evoplan.evaluation.Evaluator`, spread over a pool.

    ``X`` is cut into ``min(n, chunks)`` contiguous chunks (default: one per worker); each chunk
    is evaluated by the wrapped evaluator on a worker, and the results are put back in row
    order, so the numbers are those of the wrapped evaluator called on the whole batch (for a
    problem whose rows do not depend on each other). The evaluator is shipped to the workers
    once. A chunk lost to the infrastructure (a worker that died) is a failure of each of its
    rows, counted like any other, and the run goes on.
    """

    def __init__(self, evaluator: Callable[[np.ndarray], Evaluation], pool, chunks: int | None = None) -> None:
        self.evaluator = evaluator
        self.pool = pool
        self.chunks = chunks or pool.workers
        self._handle = pool.bind(evaluator)

    def __call__(self, X: np.ndarray) -> Evaluation:
        parts = np.array_split(np.asarray(X), min(len(X), self.chunks)) if len(X) else [X]
        results = [
            r if isinstance(r, Evaluation) else _failed(len(part), f"evaluation backend {self.pool.name}: "
                                                                   f"{type(r).__name__}: {r}")
            for part, r in zip(parts, self.pool.call(self._handle, parts))
        ]
        errors = list(dict.fromkeys(m for r in results for m in r.errors))
        return Evaluation(np.concatenate([r.f for r in results]), np.concatenate([r.failed for r in results]), errors)


def _failed(n: int, message: str) -> Evaluation:
    return Evaluation(np.full(n, np.inf), np.ones(n, dtype=bool), [message])
