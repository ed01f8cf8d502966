"""pymoo's calling conventions read as evoplan run settings (used by :mod:`evoplan.api`).

A pymoo user writes ``minimize(problem, GA(pop_size=20), ("n_gen", 5), seed=1)``. This module
turns each piece into the settings of the equivalent evoplan run:

- **termination**: pymoo's tuples (``("n_gen", n)``, ``("n_evals", n)``, ``("time", s)``,
  ``("fmin", v)``) and its Termination objects (:class:`MaximumGenerationTermination`,
  :class:`MaximumFunctionCallTermination`, :class:`TimeBasedTermination`,
  :class:`MinimumFunctionValueTermination`, and a :class:`TerminationCollection` of them)
  become the ``termination`` group. pymoo counts the initial population as generation 1 and
  evoplan as generation 0, so ``("n_gen", n)`` is evoplan's ``generations: n - 1``: the same
  number of populations, hence of evaluations, as pymoo.
- **algorithm objects**: pymoo's GA, DE, CMAES, PSO, NSGA2, NSGA3 and SMSEMOA become the
  adapter of the same algorithm (``pymoo_ga`` ...) with the object's settings. The adapter
  builds its own pymoo object from those settings, so an object carrying anything the settings
  cannot say (another crossover, a repair, ...) is refused, naming the attribute, rather than
  run as something else.
- ``pop_size`` is the population of every algorithm: GA and VEGA call it ``population`` and
  take ``pop_size`` as its alias (:class:`~evoplan.algorithms.ga.GAConfig`).

Each refusal is one line (:class:`~evoplan.errors.ConfigError`), as for a bad run file.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from .errors import ConfigError

SOURCE = "<python>"

# pymoo termination names -> evoplan termination key (pymoo.termination.get_termination)
TUPLE_NAMES = {"n_gen": "generations", "n_iter": "generations", "n_eval": "evaluations",
               "n_evals": "evaluations", "time": "seconds", "fmin": "target"}


def _generations(n: Any, what: str) -> int:
    """evoplan's ``generations`` for pymoo's ``n_gen`` (pymoo's first generation is evoplan's 0)."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer, float)) or not float(n).is_integer():
        raise ConfigError(f"{SOURCE}: termination: {what} needs a whole number of generations (got {n!r})")
    if n < 2:
        raise ConfigError(f"{SOURCE}: termination: {what} = {n}: evoplan evolves at least one generation after "
                          "the initial population (pymoo's generation 1): give 2 or more")
    return int(n) - 1


def _seconds(value: Any, what: str) -> float:
    """pymoo's time: a number of seconds or an ``"HH:MM:SS"`` string (pymoo's ``time_to_int``)."""
    if isinstance(value, str):
        from pymoo.util.misc import time_to_int

        try:
            return float(time_to_int(value))
        except ValueError:
            raise ConfigError(f"{SOURCE}: termination: {what}: expected seconds or 'HH:MM:SS' (got {value!r})") from None
    return value


def _from_tuple(spec: tuple | list) -> dict:
    if len(spec) != 2 or not isinstance(spec[0], str):
        raise ConfigError(f"{SOURCE}: termination: expected pymoo's (name, value), e.g. ('n_gen', 50) (got {spec!r})")
    name, value = spec
    if name not in TUPLE_NAMES:
        raise ConfigError(f"{SOURCE}: termination: pymoo's {name!r} has no evoplan equivalent "
                          f"(known: {', '.join(TUPLE_NAMES)})")
    key = TUPLE_NAMES[name]
    what = f"({name!r}, {value!r})"
    if key == "generations":
        return {key: _generations(value, what)}
    if key == "seconds":
        return {key: _seconds(value, what)}
    return {key: value}


def _from_object(term) -> dict:
    from pymoo.termination.collection import TerminationCollection
    from pymoo.termination.fmin import MinimumFunctionValueTermination
    from pymoo.termination.max_eval import MaximumFunctionCallTermination
    from pymoo.termination.max_gen import MaximumGenerationTermination
    from pymoo.termination.max_time import TimeBasedTermination

    name = type(term).__name__
    if isinstance(term, MaximumGenerationTermination):
        return {"generations": _generations(term.n_max_gen, f"{name}({term.n_max_gen})")}
    if isinstance(term, MaximumFunctionCallTermination):
        if not np.isfinite(term.n_max_evals):
            raise ConfigError(f"{SOURCE}: termination: {name} without n_max_evals never stops")
        return {"evaluations": term.n_max_evals}
    if isinstance(term, TimeBasedTermination):
        return {"seconds": term.max_time}
    if isinstance(term, MinimumFunctionValueTermination):
        return {"target": term.fmin}
    if isinstance(term, TerminationCollection):  # whichever stops first, as evoplan's own rule
        merged: dict = {}
        for part in term.terminations:
            for key, value in termination_settings(part).items():
                pick = max if key == "target" else min  # the first to be reached
                merged[key] = value if key not in merged else pick(merged[key], value)
        return merged
    raise ConfigError(f"{SOURCE}: termination: pymoo's {name} has no evoplan equivalent (use "
                      "MaximumGenerationTermination, MaximumFunctionCallTermination, TimeBasedTermination, "
                      "MinimumFunctionValueTermination or a tuple such as ('n_evals', 1000))")


def termination_settings(termination) -> dict | None:
    """evoplan's ``termination`` group for any of: ``None``, a number of (evoplan) generations,
    an evoplan dict, a pymoo tuple, or a pymoo Termination object (see the module docstring)."""
    if termination is None or isinstance(termination, dict):
        return termination
    if isinstance(termination, (tuple, list)):
        return _from_tuple(termination)
    if isinstance(termination, (int, np.integer)) and not isinstance(termination, bool):
        return {"generations": int(termination)}
    from pymoo.core.termination import Termination

    if isinstance(termination, Termination):
        return _from_object(termination)
    raise ConfigError(f"{SOURCE}: termination: expected a dict, a number of generations, a pymoo tuple such as "
                      f"('n_gen', 50) or a pymoo Termination (got {type(termination).__name__})")


# ---------------------------------------------------------------------------------------------
# algorithm objects


def _is_binary(algorithm) -> bool:
    from pymoo.operators.sampling.rnd import BinaryRandomSampling

    return isinstance(getattr(getattr(algorithm, "initialization", None), "sampling", None), BinaryRandomSampling)


def _duplicates_eliminated(algorithm) -> bool:
    from pymoo.core.duplicate import NoDuplicateElimination

    return not isinstance(algorithm.eliminate_duplicates, NoDuplicateElimination)


def _representation(algorithm) -> dict:
    return {"representation": "binary" if _is_binary(algorithm) else "real"}


def _ga(a) -> dict:
    return {"pop_size": a.pop_size, "eliminate_duplicates": _duplicates_eliminated(a), **_representation(a)}


def _de(a) -> dict:
    m = a.mating
    return {"pop_size": a.pop_size, "variant": f"DE/{m.selection.value}/{m.n_diffs.value}/{m.crossover.value}",
            "CR": float(m.CR.value), "F": float(m.F.value)}


def _cmaes(a) -> dict:
    return {"sigma": float(a.sigma), "pop_size": a.options.get("popsize"), "restarts": int(a.restarts)}


def _pso(a) -> dict:
    return {"pop_size": a.pop_size, "w": float(a.w), "c1": float(a.c1), "c2": float(a.c2), "adaptive": bool(a.adaptive)}


def _multi(a) -> dict:
    return {"pop_size": a.pop_size, **_representation(a)}


def _nsga3(a) -> dict:
    from pymoo.util.ref_dirs import get_reference_directions

    dirs = np.asarray(a.ref_dirs)
    for p in range(1, 200):
        ref = get_reference_directions("das-dennis", dirs.shape[1], n_partitions=p)
        if len(ref) > len(dirs):
            break
        if ref.shape == dirs.shape and np.allclose(ref, dirs):
            return {"pop_size": a.pop_size, "partitions": p, **_representation(a)}
    raise ConfigError(f"{SOURCE}: algorithm: pymoo NSGA3's ref_dirs are not Das-Dennis directions: the nsga3 "
                      "adapter builds those (setting partitions)")


# pymoo class (module, name) -> (adapter name, settings reader)
OBJECTS: dict[tuple[str, str], tuple[str, Callable[[Any], dict]]] = {
    ("pymoo.algorithms.soo.nonconvex.ga", "GA"): ("pymoo_ga", _ga),
    ("pymoo.algorithms.soo.nonconvex.de", "DE"): ("pymoo_de", _de),
    ("pymoo.algorithms.soo.nonconvex.cmaes", "CMAES"): ("pymoo_cmaes", _cmaes),
    ("pymoo.algorithms.soo.nonconvex.pso", "PSO"): ("pymoo_pso", _pso),
    ("pymoo.algorithms.moo.nsga2", "NSGA2"): ("nsga2", _multi),
    ("pymoo.algorithms.moo.nsga3", "NSGA3"): ("nsga3", _nsga3),
    ("pymoo.algorithms.moo.sms", "SMSEMOA"): ("sms_emoa", _multi),
}

# what the user, not the algorithm, decides: never compared (pymoo sets them in setup())
RUNTIME = {"problem", "termination", "output", "display", "callback", "seed", "random_state", "evaluator",
           "history", "pop", "off", "opt", "n_iter", "data", "is_initialized", "start_time", "verbose",
           "save_history", "archive", "return_least_infeasible", "options"}


def is_pymoo_algorithm(obj) -> bool:
    try:
        from pymoo.core.algorithm import Algorithm
    except ImportError:  # pragma: no cover - pymoo is a core dependency
        return False
    return isinstance(obj, Algorithm)


def _plain(value, depth: int = 0):
    """A comparable description of a pymoo setting: numbers and strings as they are, arrays by
    value, functions by name, objects by class and their attributes (a few levels deep)."""
    if value is None or isinstance(value, (bool, int, float, str, np.integer, np.floating)):
        return value
    if isinstance(value, np.ndarray):
        return ("array", value.shape, value.tobytes())
    if isinstance(value, (list, tuple)):
        return tuple(_plain(v, depth + 1) for v in value)
    if isinstance(value, dict):
        return tuple(sorted((str(k), _plain(v, depth + 1)) for k, v in value.items()))
    if callable(value) and not hasattr(value, "__dict__") or hasattr(value, "__qualname__"):
        return ("function", getattr(value, "__module__", ""), getattr(value, "__qualname__", repr(value)))
    if depth > 4 or not hasattr(value, "__dict__"):
        return ("object", type(value).__qualname__)
    return (type(value).__qualname__, tuple(sorted((k, _plain(v, depth + 1)) for k, v in vars(value).items())))


def first_difference(a, b, path: str = "") -> tuple[str, Any, Any] | None:
    """The first attribute path where two pymoo algorithms are set up differently, else None."""
    if type(a) is not type(b):
        return path.rstrip("."), type(a).__name__, type(b).__name__
    if hasattr(a, "__dict__") and not isinstance(a, type) and not callable(getattr(a, "__qualname__", None)):
        va, vb = vars(a), vars(b)
        for key in sorted(set(va) | set(vb)):
            if not path and key in RUNTIME:
                continue
            if key not in va or key not in vb:
                return f"{path}{key}", va.get(key, "(none)"), vb.get(key, "(none)")
            found = first_difference(va[key], vb[key], f"{path}{key}.")
            if found is not None:
                return found
        return None
    if _plain(a) != _plain(b):
        return path.rstrip("."), a, b
    return None


def _short(value) -> str:
    text = value if isinstance(value, str) else getattr(type(value), "__name__", repr(value))
    if isinstance(value, (int, float, bool, np.number)):
        text = repr(value)
    return text[:60]


def algorithm_settings(obj) -> tuple[str, dict]:
    """``(adapter name, settings)`` of a pymoo algorithm object, or a one-line ``ConfigError``.

    The settings are read from the object; the adapter's own pymoo object built from them must
    then be set up like the given one in every attribute (operators, their parameters,
    duplicate elimination...), else the first attribute that differs is named.
    """
    cls = type(obj)
    entry = OBJECTS.get((cls.__module__, cls.__name__))
    if entry is None:
        known = ", ".join(name for _, name in OBJECTS)
        raise ConfigError(f"{SOURCE}: algorithm: pymoo's {cls.__name__} has no evoplan adapter (adapters for: {known}; "
                          "or give an evoplan name: ga, vega, ...)")
    name, read = entry
    settings = {k: v for k, v in read(obj).items() if v is not None}
    from .config import REGISTRY

    _, model = REGISTRY[name]
    try:
        config = model(name=name, **settings)
    except ValueError as e:
        raise ConfigError(f"{SOURCE}: algorithm: pymoo {cls.__name__}: {str(e).splitlines()[-1].strip()}") from None
    reference = _reference(name, config, obj)
    found = first_difference(obj, reference)
    if found is not None:
        path, got, built = found
        raise ConfigError(f"{SOURCE}: algorithm: pymoo {cls.__name__} with {path} = {_short(got)}: the {name} adapter "
                          f"builds {_short(built)} there (its settings: {', '.join(k for k in model.model_fields if k != 'name')}); "
                          "run this one with pymoo.optimize.minimize")
    return name, settings


def _reference(name: str, config, obj):
    """The pymoo object the adapter ``name`` builds from ``config`` (never run)."""
    from .adapters.pymoo_algorithms import FACTORIES
    from .adapters.pymoo_multi import MULTI_FACTORIES

    if name in FACTORIES:
        return FACTORIES[name](config, 0)
    n_obj = np.asarray(obj.ref_dirs).shape[1] if name == "nsga3" else 2
    return MULTI_FACTORIES[name](config, 0, n_obj)

