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
import os
import time
from typing import Any, Callable, Iterable, Iterator

import numpy as np

from .errors import EvoplanError
from .evaluation import Evaluation
from .process_pool import ProcessPool, _outcome

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
    timeout = None  # a task in this process cannot be stopped

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


def _call(fn: Callable, arg):
    return fn(arg)


LOST = {"FutureCancelledError", "CancelledError"}  # a task lost with its worker or its input, not failed
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
    timeout: float | None = None  # seconds per row a chunk may run (evaluation.timeout_s)

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

    def bind(self, obj: Callable) -> list:
        """``[obj, its scattered future]``; scattered again if a restarted worker lost every copy."""
        return [obj, self.client.scatter(obj, broadcast=True, hash=False)]

    def call(self, handle: list, chunks: list) -> list:
        """Results of the chunks; chunks lost with a dying worker are run again one at a time, so
        that only the chunk that kills its worker (Dask's ``KilledWorker``) fails."""
        results = self._call(handle, chunks)
        for i in [i for i, r in enumerate(results) if type(r).__name__ in LOST]:
            results[i] = self._call(handle, [chunks[i]])[0]
        return results

    def _call(self, handle: list, chunks: list) -> list:
        if handle[1].status != "finished":  # workers restarted (a timeout, a dead worker)
            handle[1] = self.client.scatter(handle[0], broadcast=True, hash=False)
        # one graph message out and one gather back (not a round trip per chunk)
        futures = self.client.map(_call, [handle[1]] * len(chunks), chunks, pure=False)
        if self.timeout is not None:
            return self._call_with_timeout(futures, chunks)
        done = iter(self.client.gather(futures, errors="skip"))
        return [next(done) if f.status == "finished" else _outcome(f) for f in futures]

    def _call_with_timeout(self, futures: list, chunks: list) -> list:
        """Results of ``futures``; those still running after their time fail, their workers restart."""
        rounds = -(-len(chunks) // max(self.workers, 1))
        deadline = time.monotonic() + self.timeout * max((len(c) for c in chunks), default=1) * rounds
        results = []
        for f in futures:
            try:
                results.append(f.result(timeout=max(deadline - time.monotonic(), 0.0)))
            except (Exception, SystemExit) as e:  # noqa: BLE001 - a failure of this chunk's rows
                late = f.status not in ("finished", "error", "cancelled", "lost")
                results.append(TimeoutError(f"no result within timeout_s = {self.timeout:g} s per row")
                               if late else e)
        late = [f for f, r in zip(futures, results) if isinstance(r, TimeoutError)]
        if late:
            busy = [w for w, keys in self.client.processing().items() if {f.key for f in late} & set(keys)]
            self.client.cancel(late, force=True)
            if busy:  # a Python thread cannot be stopped: restart the workers that run it
                try:
                    self.client.restart_workers(busy, timeout=30)
                except Exception:  # noqa: BLE001 - workers without a nanny cannot restart
                    pass
        return results

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
        outcomes = self.pool.call(self._handle, parts)
        for r in outcomes:
            if isinstance(r, EvoplanError):  # the problem is wrong (e.g. the objective's shape): stop
                raise r
        results = [
            r if isinstance(r, Evaluation) else _failed(len(part), f"evaluation backend {self.pool.name}: "
                                                                   f"{type(r).__name__}: {r}")
            for part, r in zip(parts, outcomes)
        ]
        errors = list(dict.fromkeys(m for r in results for m in r.errors))
        return Evaluation(np.concatenate([r.f for r in results]), np.concatenate([r.failed for r in results]), errors)


def _failed(n: int, message: str) -> Evaluation:
    return Evaluation(np.full(n, np.inf), np.ones(n, dtype=bool), [message])
