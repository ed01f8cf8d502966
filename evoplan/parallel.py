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
from .evaluation import Evaluation, stack_column, stack_vectors
from .process_pool import ProcessPool, _outcome

SCHEDULER_TIMEOUT = 5.0  # seconds to reach a scheduler, and to see its first worker
POLL = 0.01  # seconds between looks at a wave's futures
NO_WORKERS_TIMEOUT = 60.0  # seconds a cluster may have no worker before a study gives up
SETTLE_TIMEOUT = 10.0  # seconds closing waits for restarted workers to come back
CLOSE_TRIES = 3  # attempts to close a local cluster a restarting nanny keeps busy
START_SLACK = 1.0  # seconds a task may take to reach a (restarted) worker, beyond its timeout
RESUME = "finished work is kept (run the same command again to resume)"
SCATTER_TRIES = 5  # broadcasts tried while workers are being replaced, before sending to one worker
log = logging.getLogger(__name__)


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


#: the local cluster's settings. No statistical profiler sampling every worker thread (CPU that
#: the workers share). No ``MALLOC_TRIM_THRESHOLD_``: distributed's nannies set it (65536) before
#: they spawn a worker, and glibc then keeps its mmap threshold fixed at 128 KiB instead of
#: raising it to the sizes a program frees, so every larger numpy temporary is a fresh mmap and
#: its page faults. A 5-axis Fountas batch of 100 plans took 0.13 s on one core with glibc's
#: defaults and 0.23 s with the variable (68 000 page faults, 0.1 s of system time): the Dask
#: workers ran at the serial speed. ``None`` drops the variable (``distributed.nanny``);
#: the BLAS threads stay at distributed's one per worker. A nanny also writes its variables
#: into this process's environment, which its workers (and any other cluster's) inherit, so
#: the variable is also kept out of the environment while evoplan's local cluster runs.
TRIM = "MALLOC_TRIM_THRESHOLD_"
QUIET_WORKERS = {"distributed.worker.profile.enabled": False,
                 f"distributed.nanny.pre-spawn-environ.{TRIM}": None}


LOST = {"FutureCancelledError", "CancelledError", "KilledWorker", "CommClosedError"}  # the worker died


def _lost(outcome):
    """A task lost with its worker (or with the input that worker held) as a ``ChildProcessError``."""
    if type(outcome).__name__ in LOST:
        return ChildProcessError(f"the worker died while evaluating these rows ({type(outcome).__name__})")
    return outcome


def _wait(futures: list, limit: float | None) -> None:
    """Until no future is pending, or ``limit`` seconds (``distributed.wait`` wants a default client)."""
    end = None if limit is None else time.monotonic() + limit
    while any(f.status == "pending" for f in futures) and (end is None or time.monotonic() < end):
        time.sleep(POLL)


def worker_slots(client) -> int:
    """Tasks a Dask cluster runs at once: the threads of *all* its workers.

    Not ``len(client.scheduler_info()["workers"])``: distributed 2025.4 to 2026.6 truncate that
    dict to 5 workers by default, which cut a population into 5 chunks on 16 workers (4x
    instead of 10x in ``runs/bench/parallel_evaluation.py``).
    """
    return int(sum(client.nthreads().values()))


def _no_workers() -> EvoplanError:
    return EvoplanError(f"dask: the cluster has had no workers for {NO_WORKERS_TIMEOUT:g} s; {RESUME}")


class DaskPool:
    """Dask distributed: a local cluster of ``workers`` processes, or the scheduler at an address."""

    name = "dask"
    timeout: float | None = None  # seconds per row a chunk may run (evaluation.timeout_s)
    _trim: str | None = None  # the environment's MALLOC_TRIM_THRESHOLD_ while a local cluster runs

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
            self._trim = os.environ.pop(TRIM, None)  # put back by close (QUIET_WORKERS)
            # no dashboard; the scheduler's HTTP endpoint on a free port (8787 may be taken); no
            # statistical profiler sampling every worker thread (CPU that n workers share)
            try:
                with dask.config.set(QUIET_WORKERS):
                    self.cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                                dashboard_address=None, scheduler_kwargs={"dashboard_address": ":0"},
                                                silence_logs=logging.CRITICAL)  # lost workers are handled here
                self.client = Client(self.cluster, set_as_default=False)
            except BaseException:
                self._restore_trim()  # no pool to close: the environment as it was
                raise
        self.workers = worker_slots(self.client) or (workers or 1)
        self.size = len(self.client.nthreads()) or (workers or 1)  # workers to scale a local cluster back to

    def submit(self, fn: Callable, *args):
        return self.client.submit(fn, *args, pure=False)

    def as_completed(self, futures: Iterable) -> Iterator:
        """The futures as they finish. A cluster left without workers (a local one whose
        nannies gave up restarting them) is scaled back up; still without any after
        ``NO_WORKERS_TIMEOUT`` seconds, a one-line error instead of waiting for ever."""
        pending, alone_since = list(futures), None
        while pending:
            done = [f for f in pending if f.status != "pending"]
            for f in done:
                pending.remove(f)
                yield f
            if done:
                continue
            if self.client.nthreads():
                alone_since = None
            else:
                alone_since = alone_since or time.monotonic()
                self._scale_up()
                if time.monotonic() - alone_since > NO_WORKERS_TIMEOUT:
                    raise _no_workers()
            time.sleep(10 * POLL)

    def bind(self, obj: Callable) -> list:
        """``[obj, its scattered future]``; scattered again if a restarted worker lost every copy."""
        return [obj, self._scatter(obj)]

    def _scatter(self, obj: Callable):
        """``obj`` sent to the workers. Broadcasting races with a worker that is dying or being
        replaced (distributed then raises "Can not use replicate to delete data", "No valid
        workers found" or a closed comm); it waits for a worker, is tried again, and last sent to
        one worker, from which the others fetch it."""
        for attempt in range(SCATTER_TRIES + 1):
            self._await_a_worker()
            try:
                return self.client.scatter(obj, broadcast=attempt < SCATTER_TRIES, hash=False)
            except (ValueError, OSError, RuntimeError):  # CommClosedError is an OSError
                time.sleep(POLL * (attempt + 1))
        raise EvoplanError(f"dask: the problem could not be sent to the workers (they kept leaving); {RESUME}")

    def _await_a_worker(self) -> None:
        """Return once the cluster has a worker; a one-line error after ``NO_WORKERS_TIMEOUT``."""
        if self.client.nthreads():
            return
        self._scale_up()
        try:
            self.client.wait_for_workers(1, timeout=NO_WORKERS_TIMEOUT)
        except (TimeoutError, OSError) as e:
            raise _no_workers() from e

    def _scale_up(self) -> None:
        """Ask a local cluster whose nannies gave up restarting workers for its size again."""
        if self.cluster is not None:
            try:
                self.cluster.scale(self.size)
            except Exception:  # noqa: BLE001 - the caller's error says what matters
                pass

    def call(self, handle: list, chunks: list) -> list:
        """One outcome per chunk (its result, or the exception it ended with), in waves of at
        most one chunk per worker slot, so that with a ``timeout`` every chunk starts at once and
        none is blamed for the time it waited behind a hanging one (the "timed out after 0 s"
        of healthy rows). Late chunks are cancelled and their workers restarted (a Python thread
        cannot be stopped; the nanny replaces the process)."""
        results: list = []
        for lo in range(0, len(chunks), max(self.workers, 1)):
            wave = chunks[lo:lo + max(self.workers, 1)]
            if handle[1].status != "finished":  # workers restarted (a timeout, a dead worker)
                handle[1] = self._scatter(handle[0])
            futures = self.client.map(_call, [handle[1]] * len(wave), wave, pure=False)
            limit = None if self.timeout is None else self.timeout * max(len(c) for c in wave) + START_SLACK
            _wait(futures, limit)
            late = [f for f in futures if f.status == "pending"]
            results += [TimeoutError(f"no result within timeout_s = {self.timeout:g} s per row")
                        if f in late else _lost(_outcome(f)) for f in futures]
            if late:
                self._restart(late)
        return results

    def _restart(self, late: list) -> None:
        busy = [w for w, keys in self.client.processing().items() if {f.key for f in late} & set(keys)]
        self.client.cancel(late, force=True)
        if busy:
            try:
                self.client.restart_workers(busy, timeout=30)
            except Exception:  # noqa: BLE001 - workers without a nanny cannot restart
                pass

    def close(self) -> None:
        """Close the client and a local cluster. A nanny still starting the worker that replaces
        a killed or restarted one makes distributed's close fail ("can only join a started
        process"); the workers are first given ``SETTLE_TIMEOUT`` s to come back, and a close
        that still fails is tried again, then left to the nannies' own exit: the run's results
        are written by then and a teardown race must not turn it into a failure."""
        try:
            if self.cluster is not None:
                try:
                    self.client.wait_for_workers(self.size, timeout=SETTLE_TIMEOUT)
                except Exception:  # noqa: BLE001 - a cluster that does not settle is closed anyway
                    pass
            self.client.close()
            for attempt in range(CLOSE_TRIES if self.cluster is not None else 0):
                try:
                    self.cluster.close()
                    return
                except Exception as e:  # noqa: BLE001 - see the docstring
                    log.debug("dask: closing the local cluster failed (%s), attempt %d", e, attempt + 1)
                    time.sleep(POLL * 10)
        finally:
            self._restore_trim()  # however the close ends

    def _restore_trim(self) -> None:
        """Put the environment's MALLOC_TRIM_THRESHOLD_ back (see :data:`QUIET_WORKERS`)."""
        if self._trim is not None:
            os.environ[TRIM] = self._trim
            self._trim = None


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
    once. A chunk lost to the infrastructure (a worker that died, a row past ``timeout_s``) has
    its rows run again one per task, and a row lost beside the one at fault once more alone:
    only the rows that kill their worker or hang fail (counted like any other failure), so the
    numbers do not depend on which worker died where, and the run goes on.
    """

    def __init__(self, evaluator: Callable[[np.ndarray], Evaluation], pool, chunks: int | None = None) -> None:
        self.evaluator = evaluator
        self.pool = pool
        self.chunks = chunks or pool.workers
        self._handle = pool.bind(evaluator)

    def __call__(self, X: np.ndarray) -> Evaluation:
        X = np.asarray(X)
        parts = np.array_split(X, min(len(X), self.chunks)) if len(X) else [X]
        results = self._outcomes(parts)
        lost = [i for i, r in enumerate(results) if not isinstance(r, Evaluation) and len(parts[i])]
        if lost:  # a worker died or a chunk ran late: find the rows at fault, one row per task
            many = [i for i in lost if len(parts[i]) > 1]
            single = iter(self._outcomes([row[None, :] for i in many for row in parts[i]]) if many else [])
            rows = [(row[None, :], results[i] if len(parts[i]) == 1 else next(single))
                    for i in lost for row in parts[i]]
            # a row lost beside the one at fault (not late: it had a worker of its own) is run alone
            rows = [(x, r if isinstance(r, (Evaluation, TimeoutError)) else self._outcomes([x])[0]) for x, r in rows]
            it = iter(r for _, r in rows)
            for i in lost:
                results[i] = _join([next(it) for _ in range(len(parts[i]))], self.pool.name)
        results = [_join([r], self.pool.name) for r in results]
        errors = list(dict.fromkeys(m for r in results for m in r.errors))
        return Evaluation(np.concatenate([r.f for r in results]), np.concatenate([r.failed for r in results]), errors,
                          stack_vectors(results), stack_column(results, "raw"),
                          stack_column(results, "cv"))

    def _outcomes(self, parts: list) -> list:
        outcomes = self.pool.call(self._handle, parts)
        for r in outcomes:
            if isinstance(r, EvoplanError):  # the problem is wrong (e.g. the objective's shape): stop
                raise r
        return outcomes


def _join(outcomes: list, backend: str) -> Evaluation:
    """One evaluation from the outcomes of consecutive one-row (or whole-chunk) tasks."""
    if len(outcomes) == 1 and isinstance(outcomes[0], Evaluation):
        return outcomes[0]
    parts = [r if isinstance(r, Evaluation) else
             _failed(1, f"evaluation backend {backend}: {type(r).__name__}: {str(r).splitlines()[0][:300] if str(r) else ''}")
             for r in outcomes]
    return Evaluation(np.concatenate([r.f for r in parts]), np.concatenate([r.failed for r in parts]),
                      list(dict.fromkeys(m for r in parts for m in r.errors)), stack_vectors(parts),
                      stack_column(parts, "raw"), stack_column(parts, "cv"))


def _failed(n: int, message: str) -> Evaluation:
    return Evaluation(np.full(n, np.inf), np.ones(n, dtype=bool), [message])
