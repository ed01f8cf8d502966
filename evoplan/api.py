"""The Python API: :func:`minimize` for a whole run, :class:`AskTell` for a loop of your own.

>>> import evoplan
>>> r = evoplan.minimize("kubota", "vega", termination={"generations": 20}, seed=1, population=20)
>>> r.x, r.f, r.evaluations                                        # doctest: +SKIP

``problem`` is a pymoo ``Problem`` object, a problem name (``"kubota"``, ``"toolpath"``, any
pymoo test problem, ``"module:Class"``) with its keyword arguments in ``params``, or a whole
run configuration as a dict (the YAML of ``evoplan run``, read as it is). The run is the very
one ``evoplan run`` makes of the same settings: same engine, budget counting and seeds.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .config import REGISTRY, RunConfig, parse_config
from .engine import RunState, run
from .multiobjective import connect, front_frame
from .runner import Prepared, best_record, execute, history_frame, prepare

__all__ = ["minimize", "Result", "AskTell", "run_config"]


class _Default(str):
    """The default algorithm name, told apart from the same name given on purpose."""


VEGA = _Default("vega")


@dataclass
class Result:
    """The outcome of :func:`minimize`.

    ``x``: the best solution's decoded variables by name (the toolpath tool by its id);
    ``f``: its objective value (with several objectives: the lowest Eq. 9 weighted sum);
    ``genotype``: the searched row (bits for GA/VEGA, unit-cube reals for real-coded adapters);
    ``history``: one row per generation (the columns of ``history.csv``); ``evaluations`` and
    ``failures`` counted by the engine; ``front``: the non-dominated points of a
    multi-objective run (the table of ``pareto.csv``), else ``None``; ``out``: the results
    folder when one was written.
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

    @classmethod
    def of(cls, prepared: Prepared, state: RunState, out: Path | None = None) -> "Result":
        record = best_record(prepared, state)
        front = None
        if hasattr(state.algorithm, "front_F"):
            front = front_frame(prepared.evaluator.problem, prepared.space, state.algorithm)
        return cls(x=record["variables"], f=state.best_f,
                   genotype=None if state.best_g is None else state.best_g.copy(),
                   history=history_frame(state), evaluations=state.evaluations, failures=state.failures,
                   generations=state.algorithm.generation, stop_reason=state.stop_reason,
                   failure_messages=list(state.errors), seed=record["seed"], algorithm=record["algorithm"],
                   problem=record["problem"], front=front, out=out)


def problem_label(problem) -> str:
    """``module:Class`` of a problem object: what results files record as its name."""
    return f"{type(problem).__module__}:{type(problem).__qualname__}"


def run_config(problem, algorithm: str = VEGA, *, termination=None, seed: int | None = None,
               params: dict | None = None, bits: int | None = None, gray: bool | None = None,
               variables: dict | None = None, **settings) -> tuple[RunConfig, Any]:
    """The validated run configuration of these arguments, and the problem object if one was given.

    With a config dict, the arguments given here override its entries (``algorithm`` and
    ``settings`` replace its ``algorithm`` group when an algorithm is named or settings given).
    """
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
        data["termination"] = termination if isinstance(termination, dict) else {"generations": int(termination)}
    if seed is not None:
        data["seed"] = seed
    data.setdefault("name", prob.get("name", "run").split(":")[-1])
    return parse_config(data, "<python>"), obj


def minimize(problem, algorithm: str = VEGA, *, termination=None, seed: int | None = None,
             params: dict | None = None, bits: int | None = None, gray: bool | None = None,
             variables: dict | None = None, out: str | Path | None = None, progress: bool = False,
             **settings) -> Result:
    """Minimize ``problem`` with ``algorithm`` (``"ga"``, ``"vega"``, ``"pymoo_de"``, ``"nsga2"``...).

    ``termination``: a dict (``{"generations": 50}``, ``evaluations``, ``target``, ``seconds``)
    or a number of generations; default 50 generations. ``seed`` (default 0) seeds the run's
    generator. ``params``: the problem's keyword arguments when it is given by name. ``bits``,
    ``gray``, ``variables``: the binary codec (as in a run file's ``problem`` group).
    ``settings``: the algorithm's settings (``population=20``, ``virus={"count": 5}``, ...).
    ``out``: a results folder to write exactly as ``evoplan run --out`` does (else nothing is
    written). Bad settings raise :class:`evoplan.errors.ConfigError` with a one-line message.
    """
    config, obj = run_config(problem, algorithm, termination=termination, seed=seed, params=params,
                             bits=bits, gray=gray, variables=variables, **settings)
    prepared = prepare(config, "<python>", problem=obj)
    if out is not None:
        state = execute(prepared, Path(out), progress=progress)
        return Result.of(prepared, state, Path(out))
    state = prepared.new_state()
    connect(prepared.evaluator, state.algorithm, prepared.search.decode)
    run(state, prepared.search, prepared.evaluator, prepared.termination)
    return Result.of(prepared, state)


class AskTell:
    """GA, VEGA or an adapter, driven by your own loop: ``ask`` phenotypes, ``tell`` their values.

    >>> opt = evoplan.AskTell("kubota", "vega", seed=1, population=20)
    >>> while opt.generation < 30:
    ...     X = opt.ask()                 # (m, d) decoded rows, columns opt.names
    ...     opt.tell(my_objective(X))     # (m,) values to minimize; inf for a failure

    VEGA asks twice per generation (the offspring, then the infected hosts); ``tell`` returns
    True when a generation has ended. ``problem`` gives the variables (a pymoo problem, a
    name, or an :class:`evoplan.space.Space`); nothing is evaluated here but what you tell.
    """

    def __init__(self, problem, algorithm: str = "vega", *, seed: int = 0, params: dict | None = None,
                 bits: int = 23, gray: bool = False, variables: dict | None = None, **settings) -> None:
        from .adapters import search_space
        from .problem_factory import build_space, make_problem
        from .space import Space

        if isinstance(problem, Space):
            self.space = problem
        else:
            obj = make_problem(problem, params) if isinstance(problem, str) else problem
            config, _ = run_config(obj, algorithm, seed=seed, bits=bits, gray=gray, variables=variables,
                                   **settings)
            self.space = build_space(obj, bits, gray, config.problem.variables)
        config, _ = run_config({"problem": {"name": "space"}}, algorithm, seed=seed, **settings)
        algo_cls, _ = REGISTRY[config.algorithm.name]
        if getattr(algo_cls, "multi_objective", False):
            raise ValueError(f"{config.algorithm.name}: ask/tell here is single-objective; use minimize()")
        self.search = search_space(config.algorithm, self.space)
        self.rng = np.random.default_rng(seed)
        self.algorithm = algo_cls(config.algorithm, self.search.n_bits, self.rng)
        self.evaluations = 0
        self.best_f, self.best_x = np.inf, None
        self._asked: np.ndarray | None = None

    @property
    def names(self) -> list[str]:
        return self.space.names

    @property
    def generation(self) -> int:
        """Generations completed (-1 before the initial population is told)."""
        return self.algorithm.generation

    def ask(self) -> np.ndarray:
        """The next batch to evaluate, decoded: ``(m, d)`` floats (a choice as its index)."""
        self._asked = self.algorithm.ask()
        return self.search.decode(self._asked)

    def tell(self, f) -> bool:
        """The objective values of the last batch; True when a generation has ended."""
        if self._asked is None:
            raise RuntimeError("tell() without ask()")
        f = np.where(np.isfinite(np.asarray(f, dtype=float)), f, np.inf).reshape(-1)
        if len(f) != len(self._asked):
            raise ValueError(f"expected {len(self._asked)} values, got {len(f)}")
        self.evaluations += len(f)
        i = int(np.argmin(f))
        if f[i] < self.best_f:
            self.best_f = float(f[i])
            self.best_x = self.space.named(self.search.decode(self._asked[i : i + 1])[0])
        self._asked = None
        return self.algorithm.tell(f)

    def named(self, x) -> dict[str, Any]:
        """One decoded row as ``{name: value}`` (a choice as the choice itself)."""
        return self.space.named(x)
