"""The Python API: :func:`minimize` for a whole run, :class:`AskTell` for a loop of your own.

>>> import evoplan
>>> r = evoplan.minimize("kubota", "vega", termination={"generations": 20}, seed=1, population=20)
>>> r.x, r.f, r.evaluations                                        # doctest: +SKIP

``problem`` is a pymoo ``Problem`` object, a problem name (``"kubota"``, ``"toolpath"``, any
pymoo test problem, ``"module:Class"``) with its keyword arguments in ``params``, or a whole
run configuration as a dict (the YAML of ``evoplan run``, read as it is). The run is the very
one ``evoplan run`` makes of the same settings: same engine, budget counting and seeds.

pymoo's conventions work as in pymoo (:mod:`evoplan.pymoo_idioms`): an algorithm object
(``GA(pop_size=20)``) runs through evoplan's adapter of it, ``termination`` takes pymoo's
tuples and Termination objects, ``pop_size`` is every algorithm's population, ``callback``,
``verbose`` and ``save_history`` do what pymoo's do, and :class:`Result` has pymoo's ``X``,
``F``, ``CV``, ``feasible`` and ``exec_time``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .cache import EvaluationCache
from .config import REGISTRY, RunConfig, parse_config
from .engine import RunState, lookup, run, settle
from .evaluation import Evaluation
from .feasibility import FeasibleBest, pymoo_arrays
from .generation_hooks import GenerationHooks, Population
from .multiobjective import connect, front_frame
from .pymoo_idioms import algorithm_settings, is_pymoo_algorithm, termination_settings
from .runner import Prepared, best_record, execute, history_frame, prepare

__all__ = ["minimize", "Result", "AskTell", "run_config", "Population"]


class _Default(str):
    """The default algorithm name, told apart from the same name given on purpose."""


VEGA = _Default("vega")


@dataclass
class Result:
    """The outcome of :func:`minimize`.

    evoplan's view: ``x``: the best solution's decoded variables by name (the toolpath tool by
    its id); ``f``: its objective value as the engine ranks it (with constraints: penalized;
    with several objectives: the lowest Eq. 9 weighted sum); ``genotype``: the searched row
    (bits for GA/VEGA, unit-cube reals for real-coded adapters); ``history``: one row per
    generation (the columns of ``history.csv``); ``evaluations`` and ``failures`` counted by the
    engine; ``front``: the non-dominated points of a multi-objective run (the table of
    ``pareto.csv``), else ``None``; ``out``: the results folder when one was written.

    pymoo's view (shapes as pymoo's ``Result``): ``X`` ``(n_var,)`` and ``F`` ``(1,)`` of the
    best *feasible* point, ``CV`` ``(1,)`` its constraint violation; with several objectives the
    non-dominated set, ``(k, n_var)``, ``(k, n_obj)``, ``(k, 1)``; all three ``None`` and
    ``feasible`` False when no feasible point was found (pymoo's ``X = None``). ``exec_time``:
    the run's wall time in seconds. ``populations``: with ``save_history=True``, one
    :class:`~evoplan.generation_hooks.Population` per generation, else empty.
    """

    x: dict[str, Any] | None
    f: float
    genotype: np.ndarray | None
    history: pd.DataFrame
    evaluations: int
    failures: int
    generations: int = 0
    stop_reason: str | None = None
    failure_messages: list[str] = field(default_factory=list)
    seed: int = 0
    algorithm: str = ""
    problem: str = ""
    front: pd.DataFrame | None = None
    out: Path | None = None
    X: np.ndarray | None = None
    F: np.ndarray | None = None
    CV: np.ndarray | None = None
    feasible: bool = False
    exec_time: float = 0.0
    populations: list[Population] = field(default_factory=list)

    @classmethod
    def of(cls, prepared: Prepared, state: RunState, out: Path | None = None, tracker: FeasibleBest | None = None,
           hooks: GenerationHooks | None = None) -> "Result":
        record = best_record(prepared, state)
        front = front_arrays = None
        if hasattr(state.algorithm, "front_F"):
            front = front_frame(prepared.evaluator.problem, prepared.space, state.algorithm)
            front_arrays = (state.algorithm.front_X, state.algorithm.front_F)
        best_X = None if state.best_g is None else prepared.search.decode(state.best_g[None, :])[0]
        arrays = pymoo_arrays(prepared.evaluator.problem, tracker, best_X, state.best_f, front_arrays)
        return cls(x=record["variables"], f=state.best_f,
                   genotype=None if state.best_g is None else state.best_g.copy(),
                   history=history_frame(state), evaluations=state.evaluations, failures=state.failures,
                   generations=state.algorithm.generation, stop_reason=state.stop_reason,
                   failure_messages=list(state.errors), seed=record["seed"], algorithm=record["algorithm"],
                   problem=record["problem"], front=front, out=out, **arrays, exec_time=float(state.elapsed),
                   populations=list(hooks.populations or []) if hooks is not None else [])


def problem_label(problem) -> str:
    """``module:Class`` of a problem object: what results files record as its name."""
    return f"{type(problem).__module__}:{type(problem).__qualname__}"


def algorithm_and_settings(algorithm, settings: dict, seed: int | None) -> tuple[Any, dict, int | None]:
    """``algorithm`` as a name with its settings, and the seed: a pymoo algorithm object gives
    its adapter's name and settings (``settings`` given here override them) and, when ``seed``
    is None, its own ``seed``."""
    if not is_pymoo_algorithm(algorithm):
        return algorithm, settings, seed
    name, from_object = algorithm_settings(algorithm)
    if seed is None and getattr(algorithm, "seed", None) is not None:
        seed = int(algorithm.seed)
    return name, {**from_object, **settings}, seed


def run_config(problem, algorithm: str = VEGA, termination=None, *, seed: int | None = None,
               params: dict | None = None, bits: int | None = None, gray: bool | None = None,
               variables: dict | None = None, **settings) -> tuple[RunConfig, Any]:
    """The validated run configuration of these arguments, and the problem object if one was given.

    With a config dict, the arguments given here override its entries (``algorithm`` and
    ``settings`` replace its ``algorithm`` group when an algorithm is named or settings given).
    """
    algorithm, settings, seed = algorithm_and_settings(algorithm, settings, seed)
    termination = termination_settings(termination)
    obj = None
    if isinstance(problem, dict):
        data = {k: (dict(v) if isinstance(v, dict) else v) for k, v in problem.items()}
        data.setdefault("termination", {"generations": 50})
    else:
        data = {"problem": {}, "termination": {"generations": 50}}
        if isinstance(problem, str):
            data["problem"]["name"] = problem
        else:
            obj = problem
            data["problem"]["name"] = problem_label(problem)
    prob = data.setdefault("problem", {})
    for key, value in (("params", params), ("bits", bits), ("gray", gray), ("variables", variables)):
        if value is not None:
            prob[key] = value
    if not isinstance(algorithm, _Default) or settings or "algorithm" not in data:
        data["algorithm"] = {"name": str(algorithm), **settings}
    if termination is not None:
        data["termination"] = termination
    if seed is not None:
        data["seed"] = seed
    data.setdefault("name", prob.get("name", "run").split(":")[-1])
    return parse_config(data, "<python>"), obj


def minimize(problem, algorithm: str = VEGA, termination=None, *, seed: int | None = None,
             params: dict | None = None, bits: int | None = None, gray: bool | None = None,
             variables: dict | None = None, out: str | Path | None = None, progress: bool = False,
             callback=None, verbose: bool = False, save_history: bool = False, **settings) -> Result:
    """Minimize ``problem`` with ``algorithm``: a name (``"ga"``, ``"vega"``, ``"pymoo_de"``,
    ``"nsga2"``...) or a pymoo algorithm object with an evoplan adapter (``GA(pop_size=20)``,
    ``DE``, ``CMAES``, ``PSO``, ``NSGA2``, ``NSGA3``, ``SMSEMOA``).

    ``termination``: an evoplan dict (``{"generations": 50}``, ``evaluations``, ``target``,
    ``seconds``), a number of evoplan generations, a pymoo tuple (``("n_gen", 50)``,
    ``("n_evals", 2000)``, ``("time", "00:01:00")``) or a pymoo Termination object; default 50
    generations. ``seed`` (default 0) seeds the run's generator. ``params``: the problem's
    keyword arguments when it is given by name. ``bits``, ``gray``, ``variables``: the binary
    codec (as in a run file's ``problem`` group). ``settings``: the algorithm's settings
    (``pop_size=20`` or ``population=20``, ``virus={"count": 5}``, ...). ``out``: a results
    folder to write exactly as ``evoplan run --out`` does (else nothing is written).
    ``callback(state)`` is called after each generation with the run's
    :class:`~evoplan.engine.RunState`; ``verbose`` prints pymoo's progress line per generation;
    ``save_history`` keeps each generation's population in ``Result.populations``. Bad
    settings raise :class:`evoplan.errors.ConfigError` with a one-line message.
    """
    config, obj = run_config(problem, algorithm, termination, seed=seed, params=params,
                             bits=bits, gray=gray, variables=variables, **settings)
    prepared = prepare(config, "<python>", problem=obj)
    hooks = GenerationHooks(prepared.search.decode, callback, verbose, save_history)
    trackers: list[FeasibleBest] = []

    def watch(evaluator) -> FeasibleBest:
        trackers.append(FeasibleBest(evaluator))
        return trackers[-1]

    if out is not None:
        state = execute(prepared, Path(out), progress=progress, on_generation=hooks or None, wrap_evaluator=watch)
        return Result.of(prepared, state, Path(out), trackers[-1] if trackers else None, hooks)
    state = prepared.new_state()
    connect(prepared.evaluator, state.algorithm, prepared.search.decode)
    tracker = watch(prepared.evaluator)
    run(state, prepared.search, tracker, prepared.termination, on_generation=hooks or None)
    return Result.of(prepared, state, tracker=tracker, hooks=hooks)


class AskTell:
    """GA, VEGA or an adapter, driven by your own loop: ``ask`` phenotypes, ``tell`` their values.

    >>> opt = evoplan.AskTell("kubota", "vega", seed=1, population=20)
    >>> while opt.generation < 30:
    ...     X = opt.ask()                 # (m, d) decoded rows, columns opt.names
    ...     opt.tell(my_objective(X))     # (m,) values to minimize; inf for a failure

    VEGA asks twice per generation (the offspring, then the infected hosts); ``tell`` returns
    True when a generation has ended. ``problem`` gives the variables (a pymoo problem, a
    name, or an :class:`evoplan.space.Space`); nothing is evaluated here but what you tell.

    The loop keeps the run's evaluation cache (:mod:`evoplan.cache`, ``cache`` takes the
    settings of a run file's ``cache`` group) and counts as :func:`minimize` does: ``ask``
    returns only the rows never evaluated before, each once (a genotype asked again is answered
    from the cache; a batch the cache answers entirely comes back empty: tell it an empty
    array). With the same seed and settings, and your objective being the problem's, the loop
    asks for the very rows, and ends with the very best and evaluation count, of
    ``minimize``. ``cache={"size": 0}`` asks for every row, repeats included.
    """

    def __init__(self, problem, algorithm: str = "vega", *, seed: int = 0, params: dict | None = None,
                 bits: int = 23, gray: bool = False, variables: dict | None = None, cache: dict | None = None,
                 **settings) -> None:
        from .adapters import search_space
        from .problem_factory import build_space, make_problem
        from .space import Space

        algorithm, settings, seed = algorithm_and_settings(algorithm, settings, seed)
        if isinstance(problem, Space):
            self.space = problem
        else:
            obj = make_problem(problem, params) if isinstance(problem, str) else problem
            config, _ = run_config(obj, algorithm, seed=seed, bits=bits, gray=gray, variables=variables,
                                   **settings)
            self.space = build_space(obj, bits, gray, config.problem.variables)
        data = {"problem": {"name": "space"}, **({"cache": cache} if cache is not None else {})}
        config, _ = run_config(data, algorithm, seed=seed, **settings)
        algo_cls, _ = REGISTRY[config.algorithm.name]
        if getattr(algo_cls, "multi_objective", False):
            raise ValueError(f"{config.algorithm.name}: ask/tell here is single-objective; use minimize()")
        self.search = search_space(config.algorithm, self.space)
        rng = np.random.default_rng(seed)
        self.state = RunState(algorithm=algo_cls(config.algorithm, self.search.n_bits, rng), rng=rng,
                              cache=EvaluationCache.from_config(config.cache))
        self.algorithm = self.state.algorithm
        self._pending = None
        self._clock = time.perf_counter()

    @property
    def names(self) -> list[str]:
        return self.space.names

    @property
    def generation(self) -> int:
        """Generations completed (-1 before the initial population is told)."""
        return self.algorithm.generation

    @property
    def evaluations(self) -> int:
        """Evaluations counted as :func:`minimize` counts them (the cache's ``budget`` rule)."""
        return self.state.evaluations

    @property
    def best_f(self) -> float:
        return self.state.best_f

    @property
    def best_x(self) -> dict[str, Any] | None:
        """The best row told so far as ``{name: value}``."""
        g = self.state.best_g
        return None if g is None else self.space.named(self.search.decode(g[None, :])[0])

    @property
    def history(self) -> pd.DataFrame:
        """One row per generation, the columns of ``history.csv``."""
        return history_frame(self.state)

    def ask(self) -> np.ndarray:
        """The next rows to evaluate, decoded: ``(m, d)`` floats (a choice as its index); only
        those the cache does not answer, so ``m`` may be below the batch size, or 0."""
        self._pending = lookup(self.state, self.algorithm.ask())
        return self.search.decode(self._pending.G[self._pending.todo])

    def tell(self, f) -> bool:
        """The objective values of the rows :meth:`ask` returned; True when a generation has ended."""
        pending = self._pending
        if pending is None:
            raise RuntimeError("tell() without ask()")
        f = np.asarray(f, dtype=float).reshape(-1)
        if len(f) != len(pending.todo):
            raise ValueError(f"expected {len(pending.todo)} values, got {len(f)}")
        failed = ~np.isfinite(f)
        told = Evaluation(np.where(failed, np.inf, f), failed,
                          ["the objective told a non-finite value (NaN or inf)"] if failed.any() else [])
        self._pending = None
        ended = self.algorithm.tell(settle(self.state, pending, told))
        if ended:
            self.state.elapsed = time.perf_counter() - self._clock
            self.state.record()
        return ended

    def named(self, x) -> dict[str, Any]:
        """One decoded row as ``{name: value}`` (a choice as the choice itself)."""
        return self.space.named(x)
