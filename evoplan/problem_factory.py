"""Problems by name, and the binary variable space of a problem.

Names: ``kubota`` (Fountas Eq. 13), ``toolpath`` (the toolpath engine), ``module:Class``
for a problem of your own (a pymoo ``Problem`` subclass importable from ``module``), and any
pymoo test problem (``rastrigin``, ``ackley``, ``griewank``, ``rosenbrock``, ``schwefel``,
``sphere``, ``zakharov``, ``g1``...), built with ``pymoo.problems.get_problem(name, **params)``.

A problem declares its variables either as pymoo variables in a ``variables`` attribute
(``{name: Real(bounds=...) | Integer(bounds=...) | Choice(options=...) | Binary()}``) or, like
pymoo's test problems, only through ``xl``/``xu`` (real variables ``x1..xd``).
"""

from __future__ import annotations

import importlib
import inspect
from pathlib import Path
from typing import Any, Callable

import numpy as np
from pymoo.core.problem import Problem

from .safe_yaml import short
from .space import Categorical, Integer, Real, Space

# name -> "module:attribute"; imported on first use so a problem's dependencies load only when used
PROBLEMS: dict[str, str] = {
    "kubota": "evoplan.problems.benchmarks:Kubota",
    "toolpath": "evoplan.problems.toolpath:ToolpathProblem",
}

#: a problem name that no longer exists -> the one-line hint naming its new form
REMOVED = {
    "toolpath_zoning": "toolpath_zoning: removed, write name: toolpath with machine: 3axis, "
                       "placement: drop, spacing: scallop, feed_angle: optimized, zoning: "
                       "{method: kmeans}, ranges: {zones: [1, 8]}, fixed: {step: 1}, weights: "
                       "{eq4_total: 1}, normalization: {eq4_total: [0, 1]} "
                       "(runs/choi_zoning_vega.yaml)",
}


def register(name: str, target: str) -> None:
    """Make ``target`` (``"module:Class"``) available to run files as ``problem.name: name``."""
    PROBLEMS[name.lower()] = target


def code_module(name: str) -> str | None:
    """The module that building problem ``name`` would import as user code, or ``None``.

    ``None`` for a registered name (a trusted factory of evoplan's, or one the user registered
    in this process) and for a pymoo test problem name: those build from data. Used by the
    readers of results folders (:mod:`evoplan.run_folder`), which must import nothing a
    folder names.
    """
    if name.lower() in PROBLEMS or ":" not in name:
        return None
    return name.partition(":")[0]


def _factory(name: str) -> Callable[..., Problem] | None:
    """The class (or registered factory) ``name`` stands for; ``None`` for a pymoo test problem name.

    A ``module:Class`` name imports ``module``, which runs that module's code: a run file that
    names user code runs it, as ``python -c "import module"`` would. What it names must then be
    a class deriving from pymoo's ``Problem``; any other callable (``subprocess:run``,
    ``os:system``) is refused before it is called. Names registered with :func:`register` are
    trusted factories.
    """
    if name.lower() in REMOVED:
        raise ValueError(REMOVED[name.lower()])
    registered = PROBLEMS.get(name.lower())
    target = registered or (name if ":" in name else None)
    if target is None:
        return None
    module, _, attr = target.partition(":")
    if not module or not attr:
        raise ValueError(f"{short(name)}: expected module:Class")
    try:
        obj = getattr(importlib.import_module(module), attr)
    except (ImportError, AttributeError) as e:
        raise ValueError(f"cannot import problem {short(target)}: {type(e).__name__}: {_first_line(e)}") from None
    except (Exception, SystemExit) as e:  # noqa: BLE001 - the user's module raised while being imported
        raise ValueError(f"importing module {short(module)} raised {type(e).__name__}: {_first_line(e)}") from None
    if registered is None and not (inspect.isclass(obj) and issubclass(obj, Problem)):
        raise ValueError(f"{short(target)} is not a pymoo Problem subclass: a run file may name only problem "
                         "classes (or problems registered with evoplan.problem_factory.register)")
    return obj


def _first_line(e: BaseException) -> str:
    text = str(e).strip()
    line = text.splitlines()[0] if text else "(no message)"
    return line if len(line) <= 120 else line[:117] + "..."


def make_problem(name: str, params: dict[str, Any] | None = None, base_dir: str | None = None) -> Problem:
    """Build a problem by name; ``ValueError`` with a one-line message if it cannot be.

    ``base_dir`` (the run file's folder) is passed to problems that take one and were not
    given one, so that files a run file names (a surface's control net) resolve beside it.
    """
    params = dict(params or {})
    factory = _factory(name)
    if factory is None:
        factory = _pymoo_factory(name)
    elif base_dir is not None and "base_dir" not in params and _accepts(factory, "base_dir"):
        params["base_dir"] = base_dir
    try:
        problem = factory(**params)
    except TypeError as e:
        raise ValueError(f"bad parameters for problem {short(name)}: {_first_line(e)}") from None
    except (Exception, SystemExit) as e:  # noqa: BLE001 - a problem's own validation error, in one line
        # evoplan's own problems raise one-line messages that name a file, a key and where:
        # kept whole (the length cap is for user code's messages)
        own = isinstance(e, ValueError) and name.lower() in PROBLEMS
        line = (str(e).strip().splitlines() or ["(no message)"])[0] if own else _first_line(e)
        raise ValueError(f"cannot build problem {short(name)}: {line}") from None
    if not isinstance(problem, Problem):
        raise ValueError(f"{name!r} did not build a pymoo Problem (got {type(problem).__name__})")
    return problem


def names_files(params, base_dir: Path) -> bool:
    """Does a string among ``params`` (nested) name an existing file relative to ``base_dir``?"""
    if isinstance(params, dict):
        return any(names_files(v, base_dir) for v in params.values())
    if isinstance(params, list):
        return any(names_files(v, base_dir) for v in params)
    if isinstance(params, str) and params and len(params) < 4096 and not Path(params).is_absolute():
        try:
            return (Path(base_dir) / params).is_file()
        except (OSError, ValueError):
            return False
    return False


def surface_facts(problem) -> dict[str, Any]:
    """What every output of a problem records about its surface beyond the settings (a mesh:
    the file and the measured deviation of the fit the plan was made on); {} for the rest."""
    facts = getattr(getattr(problem, "surface", None), "facts", None)
    return dict(facts()) if callable(facts) else {}


def _accepts(factory: Callable, name: str) -> bool:
    try:
        return name in inspect.signature(factory).parameters
    except (TypeError, ValueError):
        return False


def _pymoo_factory(name: str) -> Callable[..., Problem]:
    """pymoo's test problem ``name``, checked to exist before any parameter is passed."""
    from pymoo.problems import get_problem

    try:
        get_problem(name)
    except Exception as e:  # pymoo raises a bare Exception("Problem not found.")
        if "not found" in str(e).lower():
            raise ValueError(
                f"unknown problem {name!r} (evoplan: {', '.join(sorted(PROBLEMS))}, or any pymoo test problem)"
            ) from None
    return lambda **params: get_problem(name, **params)


def declared_variables(problem: Problem, bits: int) -> list:
    """The problem's variables as evoplan variables, reals getting ``bits`` bits each."""
    declared = getattr(problem, "variables", None)
    if isinstance(declared, dict) and declared:
        out = []
        for name, var in declared.items():
            kind = type(var).__name__
            if kind == "Real":
                out.append(Real(name, float(var.bounds[0]), float(var.bounds[1]), bits))
            elif kind == "Integer":
                out.append(Integer(name, int(var.bounds[0]), int(var.bounds[1])))
            elif kind == "Choice":
                out.append(Categorical(name, tuple(var.options)))
            elif kind == "Binary":
                out.append(Integer(name, 0, 1))
            else:
                raise ValueError(f"variable {name!r}: unsupported pymoo variable type {kind}")
        return out
    xl, xu = np.broadcast_to(problem.xl, problem.n_var), np.broadcast_to(problem.xu, problem.n_var)
    return [Real(f"x{i + 1}", float(lo), float(hi), bits) for i, (lo, hi) in enumerate(zip(xl, xu))]


def build_space(problem: Problem, bits: int = 23, gray: bool = False,
                overrides: dict[str, Any] | None = None) -> Space:
    """The binary space of ``problem``; ``overrides`` maps a variable name to low/high/bits."""
    variables = declared_variables(problem, bits)
    by_name = {v.name: i for i, v in enumerate(variables)}
    for name, o in (overrides or {}).items():
        if name not in by_name:
            fixed = getattr(problem, "fixed", None)
            if isinstance(fixed, dict) and name in fixed:
                raise ValueError(f"variables.{name}: fixed at {fixed[name]:g} by the problem's params "
                                 f"(fixed.{name}): not a variable, so it has no bits")
            raise ValueError(f"variables.{name}: no such variable (the problem has {', '.join(by_name)})")
        v = variables[by_name[name]]
        changes = {k: getattr(o, k) for k in ("low", "high", "bits") if getattr(o, k) is not None}
        if v.kind == "categorical" and ({"low", "high"} & changes.keys()):
            raise ValueError(f"variables.{name}: a categorical variable has no bounds")
        try:
            variables[by_name[name]] = type(v)(**{**v.__dict__, **changes})
        except ValueError as e:
            raise ValueError(f"variables.{e}") from None
    return Space(variables, gray=gray)
