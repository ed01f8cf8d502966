"""Local worker processes that survive their tasks: dead workers, hanging tasks, a dying parent.

:class:`ProcessPool` wraps ``concurrent.futures.ProcessPoolExecutor`` (workers started by a
fork server) with what an expensive, possibly badly behaved black box needs:

- **a worker that dies** (``os._exit``, a segfault, the OOM killer) breaks a
  ``ProcessPoolExecutor`` for good: every pending task fails and no new one is accepted. The
  pool is rebuilt and the chunks that were lost are reported as lost; the evaluator runs their
  rows again (see :class:`evoplan.parallel.ParallelEvaluator`) so only the row at fault fails;
- **a task that hangs**: with ``timeout`` (``evaluation.timeout_s``, seconds per row), a batch
  whose chunks are not back in time has its workers killed; the late chunks fail with a
  ``TimeoutError``, the finished ones keep their results, and the pool is rebuilt;
- **the parent dies** (SIGKILL included): each worker runs a watchdog thread that ends the
  worker within a second of the parent's disappearance, so no orphan keeps computing;
- **close** never waits for a hanging task: the workers are killed;
- **no oversubscription**: each worker's BLAS and OpenMP pools get ``cores // workers`` threads
  (at least one), as Dask's nannies do (``distributed.nanny.pre-spawn-environ``). numpy's
  OpenBLAS otherwise starts a thread per core in every worker; on 2 cores and 2 workers the four
  threads' spin-waits ate the workers' speed-up (a 5-axis Fountas batch of 200 plans: 0.37-0.44 s
  on the pool against 0.41-0.43 s serial; with one BLAS thread per worker 0.17-0.23 s).
"""

from __future__ import annotations

import multiprocessing
import os
import pickle
import threading
import time
import uuid
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures import as_completed as futures_completed
from concurrent.futures import wait as futures_wait
from concurrent.futures.process import BrokenProcessPool
from typing import Callable, Iterable, Iterator

from threadpoolctl import threadpool_limits

WATCH_INTERVAL = 0.5  # seconds between a worker's checks that its parent is alive
START_SLACK = 1.0  # seconds a task may take to reach a (new) worker, beyond its timeout
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def _outcome(future):
    """A task's result, or the exception it ended with (one chunk's loss is not the batch's)."""
    try:
        return future.result()
    except (Exception, SystemExit) as e:  # noqa: BLE001 - reported as failures of the chunk's rows
        return e


def worker_threads(workers: int) -> int:
    """BLAS / OpenMP threads for each of ``workers`` processes: the cores shared out, at least one."""
    return max(1, (os.cpu_count() or 1) // max(workers, 1))


def _start_worker(parent: int, threads: int) -> None:
    """Worker initializer: ``threads`` BLAS / OpenMP threads, and an exit as soon as the process
    ``parent`` is gone."""
    for name in THREAD_VARIABLES:  # for the libraries the worker loads later
        os.environ[name] = str(threads)
    threadpool_limits(threads)  # for those loaded already (the fork server preloads numpy, scipy)
    _watch_parent(parent)


def _watch_parent(parent: int) -> None:
    """Exit the worker as soon as the process ``parent`` is gone (a watchdog thread)."""
    def watch() -> None:
        while True:
            time.sleep(WATCH_INTERVAL)
            try:
                os.kill(parent, 0)
            except ProcessLookupError:
                os._exit(1)
            except PermissionError:  # the pid now belongs to another user's process: ours is gone
                os._exit(1)

    threading.Thread(target=watch, name="evoplan-parent-watch", daemon=True).start()


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
        self.timeout: float | None = None
        self.rebuilds = 0
        self._ctx = multiprocessing.get_context("forkserver")
        self._ctx.set_forkserver_preload(["evoplan.study.cell"])
        self.executor = self._start()

    def _start(self) -> ProcessPoolExecutor:
        return ProcessPoolExecutor(max_workers=self.workers, mp_context=self._ctx,
                                   initializer=_start_worker, initargs=(os.getpid(), worker_threads(self.workers)))

    def _kill(self) -> None:
        """Stop every worker now (running tasks included) and forget the executor."""
        processes = list((getattr(self.executor, "_processes", None) or {}).values())
        self.executor.shutdown(wait=False, cancel_futures=True)
        for p in processes:
            if p.is_alive():
                p.kill()
        for p in processes:
            p.join(timeout=5)

    def _rebuild(self) -> None:
        self._kill()
        self.executor = self._start()
        self.rebuilds += 1

    def recover(self) -> None:
        """Rebuild the executor if a dead worker broke it (every running task already failed)."""
        if getattr(self.executor, "_broken", False):
            self._rebuild()

    def submit(self, fn: Callable, *args):
        return self.executor.submit(fn, *args)

    def as_completed(self, futures: Iterable) -> Iterator:
        return futures_completed(list(futures))

    def bind(self, obj: Callable) -> tuple[str, bytes]:
        return uuid.uuid4().hex, pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)

    def call(self, handle: tuple[str, bytes], chunks: list) -> list:
        """One outcome per chunk, in waves of at most one chunk per worker (so that with a
        ``timeout`` every chunk starts at once and none is blamed for waiting behind a hanging
        one). A wave in which a worker died, or a chunk ran late, ends with the pool rebuilt:
        its finished chunks keep their results, the others fail (``ChildProcessError``,
        ``TimeoutError``) and :class:`~evoplan.parallel.ParallelEvaluator` runs their rows again
        on their own to find the one row at fault."""
        results: list = []
        for lo in range(0, len(chunks), self.workers):
            results += self._wave(handle, chunks[lo:lo + self.workers])
        return results

    def _submit(self, handle: tuple[str, bytes], chunks: list) -> list:
        """One future per chunk; ``None`` for a chunk that could not be submitted because a
        worker of this wave died meanwhile (the executor, starting a process on demand for
        the next chunk, then fails on its closed queue: ``OSError: handle is closed``, or
        raises ``BrokenProcessPool``)."""
        futures: list = []
        for c in chunks:
            try:
                futures.append(self.executor.submit(_call_blob, *handle, c))
            except BrokenProcessPool:
                if futures:  # broken by this wave's own chunks
                    futures.append(None)
                else:  # broken before this wave (a study's task killed it)
                    self._rebuild()
                    futures.append(self.executor.submit(_call_blob, *handle, c))
            except OSError:
                futures.append(None)
        return futures

    def _wave(self, handle: tuple[str, bytes], chunks: list) -> list:
        futures = self._submit(handle, chunks)
        running = [f for f in futures if f is not None]
        limit = None if self.timeout is None else self.timeout * max(len(c) for c in chunks) + START_SLACK
        _, late = futures_wait(running, timeout=limit)
        results = [BrokenProcessPool("not submitted: the pool broke") if f is None
                   else TimeoutError(f"no result within timeout_s = {self.timeout:g} s per row") if f in late
                   else _outcome(f) for f in futures]
        died = [i for i, r in enumerate(results) if isinstance(r, BrokenProcessPool)]
        for i in died:
            results[i] = ChildProcessError("the worker process died while evaluating these rows")
        if late or died:
            self._rebuild()  # late tasks' workers are still busy, a dead worker broke the executor
        return results

    def close(self) -> None:
        self._kill()
