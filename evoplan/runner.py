"""One run from a configuration: build, execute with progress and checkpoints, write results.

Everything that can be checked is checked before the results folder is created, so bad input
leaves nothing behind. The folder then holds ``config.yaml`` (every setting, defaults included)
and ``checkpoint.npz`` (data only, :mod:`evoplan.checkpoint`) while the run goes on, and at the end ``history.csv``, ``best.json`` and
``convergence.png``, each written completely or not at all.
"""

from __future__ import annotations

import errno
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from tqdm import tqdm

from . import __version__
from .adapters import search_space
from .cache import EvaluationCache
from .checkpoint import CheckpointError, check_counters, load_into
from .checkpoint import read as read_checkpoint
from .config import REGISTRY, RunConfig, load_config, read_yaml
from .engine import HISTORY_COLUMNS, Checkpointer, RunState, Termination, run, write_atomic
from .errors import ConfigError, EvoplanError
from .evaluation import Evaluator, ObjectiveShapeError
from .fixed_run import execute_fixed, is_fixed
from .multiobjective import MultiEvaluator, VectorsToLedger, add_hypervolume, connect, evaluator_for, write_front
from .parallel import ParallelEvaluator, open_pool
from .limits import check_population
from .results_folder import FolderClaim, claim
from .problem_factory import build_space, make_problem
from .space import Space

CHECKPOINT = "checkpoint.npz"
DISK_ERRORS = {errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EPERM, errno.EIO}


@dataclass
class Prepared:
    """A validated run, ready to start: nothing has touched the disk yet."""

    config: RunConfig
    source: str
    space: Space
    evaluator: Evaluator
    termination: Termination

    @property
    def fingerprint(self) -> str:
        return json.dumps(self.config.fingerprint(), sort_keys=True)

    @property
    def search(self):
        """What the algorithm searches: the binary space, or (real-coded adapters) its unit cube."""
        return search_space(self.config.algorithm, self.space)

    def new_state(self) -> RunState:
        algo_cls, _ = REGISTRY[self.config.algorithm.name]
        rng = np.random.default_rng(self.config.seed)
        extra = {"n_obj": self.evaluator.problem.n_obj} if getattr(algo_cls, "multi_objective", False) else {}
        algorithm = algo_cls(self.config.algorithm, self.search.n_bits, rng, **extra)
        cache = EvaluationCache.from_config(self.config.cache, expected_evaluations(self.config))
        return RunState(algorithm=algorithm, rng=rng, fingerprint=self.fingerprint, cache=cache)


def expected_evaluations(config: RunConfig) -> int | None:
    """The evaluations a run will likely make: its evaluation budget, else its generations
    times its population (a hint for sizing the cache's index); None when only time bounds it."""
    t = config.termination
    population = getattr(config.algorithm, "population", None)
    guesses = [t.evaluations] if t.evaluations is not None else []
    if t.generations is not None and population is not None:
        guesses.append(t.generations * population)
    return min(guesses) if guesses else None


def prepare(config: RunConfig, source: str = "<config>", problem=None) -> Prepared:
    """Build problem, space and evaluator; any bad setting is a one-line ``ConfigError``.

    ``problem``: a pymoo problem object to use instead of building ``config.problem.name``
    (the Python API passes the user's problem this way)."""
    p = config.problem
    if problem is None:
        try:
            base_dir = str(Path(source).resolve().parent) if Path(source).is_file() else None
            problem = make_problem(p.name, p.params, base_dir)
        except ValueError as e:
            raise ConfigError(f"{source}: problem: {e}") from None
    try:
        space = build_space(problem, p.bits, p.gray, p.variables)
        evaluator = evaluator_for(problem, config, source)
    except ValueError as e:
        raise ConfigError(f"{source}: problem.{e}") from None
    threads = getattr(getattr(problem, "simulated", None), "threads", 1)
    if threads > 1 and config.evaluation.backend != "serial":
        raise ConfigError(f"{source}: problem.params.simulation.threads: {threads} threads need evaluation.backend: "
                          f"serial (the {config.evaluation.backend} backend already uses the cores)")
    if getattr(getattr(problem, "simulated", None), "screening", None) is not None:
        if config.evaluation.backend != "serial":  # the screen learns from every simulation of the run
            raise ConfigError(f"{source}: problem.params.simulation.screening: needs evaluation.backend: serial "
                              f"(use simulation.threads for the cores), not {config.evaluation.backend}")
        if problem.n_obj != 1:
            raise ConfigError(f"{source}: problem.params.simulation.screening: ranks plans by one objective "
                              "(weights), not by objectives")
    t = config.termination
    prepared = Prepared(config, source, space, evaluator, Termination(t.generations, t.evaluations, t.target, t.seconds))
    if space.n_var:  # else every decision is fixed: one evaluation, no population
        check_population(config.algorithm, prepared.search.n_bits, space.n_var, source)
    return prepared


def prepare_file(path: str | Path, seed: int | None = None) -> Prepared:
    return prepare(load_config(path, seed), str(path))


def default_out(config: RunConfig) -> Path:
    stamp = time.strftime("%Y%m%d-%H%M%S")
    return Path("results") / f"{config.name}-seed{config.seed}-{stamp}"


def recorded_config(prepared: Prepared) -> dict:
    """What ``config.yaml`` records: every setting, and, when the problem's params name files
    relative to the run file (a mesh, a control net), that folder as ``params.base_dir``, so
    that ``simulate --run`` and ``machine --from-run`` find them from the results folder."""
    from .problem_factory import names_files

    data = prepared.config.resolved()
    source = Path(prepared.source)
    params = (data.get("problem") or {}).get("params")
    if isinstance(params, dict) and "base_dir" not in params and source.is_file():
        base = source.resolve().parent
        if names_files(params, base):
            params["base_dir"] = str(base)
    return data


def start_folder(prepared: Prepared, out: Path, state: RunState, checkpointer: Checkpointer) -> FolderClaim:
    """Create and lock ``out`` for a new run: its first checkpoint, then ``config.yaml``.

    Refuses a folder that holds files or that another run holds. A run killed at any point
    leaves a folder that is either empty (start it again) or holds a checkpoint (resume it).
    """
    folder = claim(out, new=True)
    try:
        checkpointer.save(state)  # generation 0: resumable before the first evaluation
        write_atomic(out / "config.yaml", yaml.safe_dump(recorded_config(prepared), sort_keys=False).encode())
    except OSError as e:
        folder.abandon()
        raise ConfigError(f"{out}: cannot write the results folder ({e.strerror or e})") from None
    return folder


def resume_state(prepared: Prepared, out: Path) -> RunState:
    """The checkpointed state in ``out``, if it was made by this very configuration.

    The checkpoint is data (:mod:`evoplan.checkpoint`): it is loaded into a fresh state built
    from the run file, after its checksum and fingerprint are checked; nothing in it is run.
    """
    if is_fixed(prepared):
        raise ConfigError(f"{prepared.source}: every decision is fixed: the run is one evaluation with "
                          f"no checkpoint; run it again with --out (a new folder) instead of --resume {out}")
    path = out / CHECKPOINT
    if not path.is_file():
        hint = f" (killed before its first checkpoint: start it again with --out {out})" if out.is_dir() else ""
        raise ConfigError(f"{out}: no {CHECKPOINT} to resume from{hint}")
    try:
        meta, arrays = read_checkpoint(path)
    except CheckpointError as e:
        raise ConfigError(f"{path}: cannot resume: {e}") from None
    if meta.get("fingerprint") != prepared.fingerprint:
        try:
            before = json.loads(meta.get("fingerprint") or "{}")
        except (TypeError, ValueError):
            before = {}
        now = prepared.config.fingerprint()
        keys = [k for k in now if now.get(k) != before.get(k)] or ["its fingerprint"]
        raise ConfigError(
            f"{prepared.source}: differs from the configuration of {out} in {', '.join(keys)}: "
            "resume with the same file and seed"
        )
    try:
        state = load_into(meta, arrays, prepared.new_state())
        check_counters(state, prepared.termination)
        return state
    except CheckpointError as e:
        raise ConfigError(f"{path}: cannot resume: {e}") from None


def execute(prepared: Prepared, out: Path, resume: bool = False, progress: bool | None = None,
            on_generation=None, wrap_evaluator=None) -> RunState:
    """Run to termination, checkpointing into ``out``, then write the results files.

    ``on_generation(state)`` is called after each generation (after the progress bar);
    ``wrap_evaluator(evaluator)`` returns the evaluator the engine calls instead (the Python
    API watches the evaluations this way, :class:`evoplan.feasibility.FeasibleBest`).

    The evaluation backend is opened before the folder is touched (an unreachable scheduler
    leaves nothing behind); a new run writes its first checkpoint before the first evaluation,
    so a run killed at any moment can be resumed. A disk that fills up or turns read-only is a
    one-line error; the last complete checkpoint stays resumable.
    """
    if is_fixed(prepared) and not resume:
        return execute_fixed(prepared, out)
    cfg = prepared.config
    state = resume_state(prepared, out) if resume else None
    e = cfg.evaluation
    pool = open_pool(e.backend, e.workers, e.scheduler, label=f"{prepared.source}: evaluation.scheduler",
                     timeout=e.timeout_s) if e.backend != "serial" else None
    folder = None
    try:
        checkpointer = Checkpointer(out / CHECKPOINT, cfg.checkpoint.every_generations, cfg.checkpoint.every_seconds)
        if state is None:
            state = prepared.new_state()
            connect(prepared.evaluator, state.algorithm, prepared.search.decode)
            folder = start_folder(prepared, out, state, checkpointer)
        else:
            folder = claim(out, new=False)
            connect(prepared.evaluator, state.algorithm, prepared.search.decode)
        evaluator = ParallelEvaluator(prepared.evaluator, pool, e.chunks) if pool else prepared.evaluator
        if pool and isinstance(prepared.evaluator, MultiEvaluator):
            evaluator = VectorsToLedger(evaluator, prepared.evaluator)  # the workers' vectors, kept here
        if wrap_evaluator is not None:
            evaluator = wrap_evaluator(evaluator)
        with _progress_bar(prepared.termination, state, progress) as update:
            run(state, prepared.search, evaluator, prepared.termination, checkpointer, _chain(update, on_generation))
        write_results(prepared, state, out)
    except ObjectiveShapeError as err:  # a bug of the problem, found in the first batch
        if folder is not None and not state.history:
            folder.abandon()  # nothing of the run is worth keeping
            folder = None
        raise EvoplanError(f"{prepared.source}: {err}") from None
    except OSError as err:
        if err.errno not in DISK_ERRORS:
            raise
        raise EvoplanError(f"{out}: cannot write ({err.strerror}); the last checkpoint is kept: "
                           f"free space and --resume {out}") from None
    finally:
        if pool is not None:
            pool.close()
        if folder is not None:
            folder.release()
    return state


def _chain(*hooks):
    """One ``on_generation`` function calling each of ``hooks`` that is not None, in order."""
    hooks = [h for h in hooks if h is not None]
    return (lambda state: [h(state) for h in hooks]) if len(hooks) > 1 else hooks[0]


class _progress_bar:
    """A tqdm bar over generations (or evaluations) on stderr; off when stderr is not a terminal."""

    def __init__(self, termination: Termination, state: RunState, enabled: bool | None) -> None:
        self.by_gen = termination.generations is not None
        total = termination.generations if self.by_gen else termination.evaluations
        done = max(state.algorithm.generation, 0) if self.by_gen else state.evaluations
        disable = None if enabled is None else not enabled
        self.bar = tqdm(total=total, initial=min(done, total or done), unit="gen" if self.by_gen else "eval",
                        disable=disable, file=sys.stderr, dynamic_ncols=True, leave=True)

    def __enter__(self):
        def update(state: RunState) -> None:
            now = state.algorithm.generation if self.by_gen else state.evaluations
            self.bar.update(max(0, min(now, self.bar.total or now) - self.bar.n))
            self.bar.set_postfix(best=f"{state.best_f:.4g}", evals=state.evaluations, refresh=False)
        return update

    def __exit__(self, *exc) -> None:
        self.bar.close()


def history_frame(state: RunState) -> pd.DataFrame:
    return add_hypervolume(pd.DataFrame(state.history, columns=list(HISTORY_COLUMNS)), state.algorithm)


def best_record(prepared: Prepared, state: RunState) -> dict:
    """What ``best.json`` holds: the best solution decoded to named variables, and the run's counts."""
    cfg = prepared.config
    best = {"objective": state.best_f if np.isfinite(state.best_f) else None, "variables": None, "genotype": None}
    if state.best_g is not None:
        best["variables"] = prepared.space.named(prepared.search.decode(state.best_g[None, :])[0])
        if state.best_g.dtype == bool:
            best["genotype"] = "".join("1" if b else "0" for b in state.best_g)
    from .problem_factory import surface_facts

    facts = surface_facts(prepared.evaluator.problem)
    return {
        **best,
        **({"surface": facts} if facts else {}),
        "evaluations": state.evaluations,
        "cache_hits": state.cache_hits,  # genotypes answered by the cache (see cache.budget)
        "generations": state.algorithm.generation,
        "failures": state.failures,
        "failure_messages": state.errors,
        "stop_reason": state.stop_reason,
        "seed": cfg.seed,
        "algorithm": cfg.algorithm.name,
        "problem": cfg.problem.name,
        "wall_seconds": round(state.elapsed, 3),
        "space": prepared.space.describe(),
        "evoplan_version": __version__,
    }


def write_results(prepared: Prepared, state: RunState, out: Path, extra: dict | None = None) -> None:
    """The results files; ``best.json`` last, so that it marks a run whose results are all written.
    ``extra``: keys added to ``best.json`` (a fixed run's plan and criteria)."""
    history = history_frame(state)
    write_atomic(out / "history.csv", history.to_csv(index=False).encode())
    record = {**best_record(prepared, state), **(extra or {})}
    if prepared.config.output.plot:
        from .plots import convergence_png  # matplotlib loads only when a figure is drawn

        title = f"{prepared.config.name}: {prepared.config.algorithm.name} on {prepared.config.problem.name}"
        write_atomic(out / "convergence.png", convergence_png(history, title))
    write_artifacts(prepared, state, out)
    write_front(prepared, state.algorithm, out)
    write_atomic(out / "best.json", (json.dumps(record, indent=2) + "\n").encode())


def write_artifacts(prepared: Prepared, state: RunState, out: Path) -> None:
    """Files the problem makes of the best solution (``artifacts(x) -> {file name: bytes}``).

    A problem opts in by defining ``artifacts``; the toolpath problem draws its CC pattern and
    writes an APT CL file this way. A failure here is reported but loses none of the results.
    """
    artifacts = getattr(prepared.evaluator.problem, "artifacts", None)
    if not callable(artifacts) or state.best_g is None:
        return
    x = prepared.search.decode(state.best_g[None, :])[0]
    try:
        files = artifacts(x)
    except Exception as e:  # noqa: BLE001 - a problem's plotting or export must not sink the run
        print(f"evoplan: warning: the problem's result files were not written: {type(e).__name__}: {e}",
              file=sys.stderr)
        return
    for name, data in files.items():
        write_atomic(out / Path(name).name, data)


def resume_seed(out: Path) -> int | None:
    """The seed recorded in a results folder's ``config.yaml`` (so ``--resume`` needs no ``--seed``)."""
    try:
        return int(read_yaml(out / "config.yaml")["seed"])
    except (ConfigError, KeyError, TypeError, ValueError):
        return None
