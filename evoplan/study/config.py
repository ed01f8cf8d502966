"""A study file, validated once at the edge: the grid, the budget, the statistics.

Layout::

    name: compare_benchmarks          # optional, defaults to the file name
    seed: 2024                        # study seed: every run's seed is derived from it
    seeds: 30                         # repetitions of every (algorithm, problem, level)
    budget: {evaluations: 1000, per_dimension: true}   # + generations, target, seconds
    problems:
      - {name: kubota}
      - {name: rastrigin, dimensions: [2, 10]}          # n_var = 2, then 10
      - {name: bbob-f3, dimensions: [5], label: bbob-rastrigin}
    algorithms:
      - {name: ga, population: 20}                      # evoplan's settings, as in a run file
      - {name: pymoo_de, label: de, pop_size: 20}       # an adapter and its settings
    factors:                                            # optional: one factor at a time
      algorithm: vega                                   # the label of the entry varied
      vary: {virus.count: [2, 5, 7, 10], virus.infection_rate: [0.1, {virus.infection_rate: 1.0}]}
    statistics: {reference: ga, test: signed_rank, alpha: 0.05, targets: null, rope: 0.0}
    output: {plots: true, ioh: true}
    cache: {size: 100000, budget: distinct}   # see evoplan/cache.py

Every name is checked here (algorithms, problems, dimensions, every factor level's settings),
so a bad study stops with one line before any run starts.
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from ..cache import CacheConfig
from ..config import REGISTRY, SafeName, TerminationConfig, VariableOverride, read_yaml
from ..errors import ConfigError, EvoplanError
from ..extras import require
from ..safe_yaml import key_text, short
from ..problem_factory import build_space, make_problem
from .bbob import resolve_problem_name



MAX_SEEDS = 100_000  # repetitions of a cell; more is a typo, not a study
MAX_CELLS = 1_000_000  # runs in one study (each is a results row and a file)


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class ProblemSpec(_Strict):
    name: str
    label: str | None = None
    params: dict[str, Any] = Field(default_factory=dict)
    dimensions: list[int] | None = Field(None, min_length=1, description="n_var values; None: the problem's own")
    bits: int = Field(23, ge=1, le=52)
    gray: bool = False
    variables: dict[str, VariableOverride] = Field(default_factory=dict)
    constraint_penalty: float = Field(1e6, ge=0)

    @field_validator("dimensions")
    @classmethod
    def _positive(cls, v):
        if v is not None and any(d < 1 for d in v):
            raise ValueError(f"dimensions must be at least 1, got {v}")
        return v


class BudgetConfig(TerminationConfig):
    """The termination of every run; ``per_dimension`` multiplies ``evaluations`` by ``n_var``."""

    per_dimension: bool = False


class FactorsConfig(_Strict):
    algorithm: str = Field(description="label of the algorithm entry whose settings vary")
    vary: dict[str, list[Any]] = Field(min_length=1, description="dotted setting -> levels")

    @field_validator("vary")
    @classmethod
    def _levels(cls, v):
        for key, levels in v.items():
            if not levels:
                raise ValueError(f"{key}: no levels (give at least one value)")
        return v


class StudyEvaluation(_Strict):
    """How every cell's evaluations are bounded (the backend is the command line's)."""

    timeout_s: float | None = Field(None, gt=0, le=86400, description="an evaluation past this fails its rows only")


class StatisticsConfig(_Strict):
    reference: str | None = Field(None, description="algorithm label the others are tested against; default: first")
    test: Literal["signed_rank", "rank_sum"] = "signed_rank"
    alpha: float = Field(0.05, gt=0, lt=1)
    targets: list[float] | None = Field(None, description="ECDF precisions f - f_ref; default 10^2 .. 10^-8")
    rope: float = Field(0.0, ge=0, description="Bayesian signed-rank: region of practical equivalence, objective units")


class OutputConfig(_Strict):
    plots: bool = True
    ioh: bool = Field(True, description="export every run in IOHprofiler format (ioh/ folder)")


class StudyConfig(_Strict):
    name: SafeName | None = None
    seed: int = Field(0, ge=0)
    seeds: int = Field(30, ge=1, le=MAX_SEEDS, description="repetitions of every cell")
    budget: BudgetConfig
    problems: list[ProblemSpec] = Field(min_length=1)
    algorithms: list[dict[str, Any]] = Field(min_length=1)
    factors: FactorsConfig | None = None
    statistics: StatisticsConfig = StatisticsConfig()
    output: OutputConfig = OutputConfig()
    cache: CacheConfig = CacheConfig()  # every run's evaluation cache and budget counting
    evaluation: StudyEvaluation = StudyEvaluation()

    @model_validator(mode="after")
    def _algorithm_entries(self):
        for i, entry in enumerate(self.algorithms):
            if "name" not in entry:
                raise ValueError(f"algorithms[{i}].name: missing (known: {', '.join(REGISTRY)})")
        return self

    def resolved(self) -> dict[str, Any]:
        return self.model_dump(mode="json")


def _loc(loc: tuple) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{key_text(part)}" if out else key_text(part))
    return out


def _first_error(error: ValidationError) -> str:
    first = error.errors()[0]
    msg = first["msg"].removeprefix("Value error, ")
    if first["type"] == "missing":
        msg = "missing"
    elif not isinstance(first.get("input"), dict) and first["type"] != "value_error":
        msg += f" (got {short(first.get('input'))})"
    where = _loc(tuple(first["loc"]))
    return f"{where}: {msg}" if where else msg


def set_dotted(data: dict, key: str, value: Any) -> dict:
    """A copy of ``data`` with ``key`` (``virus.count``) set to ``value``."""
    out = copy.deepcopy(data)
    node = out
    *path, last = key.split(".")
    for part in path:
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise ValueError(f"{key}: {part} is not a group of settings")
    node[last] = value
    return out


def algorithm_settings(entry: dict[str, Any], where: str, source: str) -> tuple[str, dict[str, Any]]:
    """``(label, resolved settings)`` of one algorithm entry; one-line ``ConfigError`` if bad."""
    entry = dict(entry)
    label = str(entry.pop("label", entry.get("name")))
    name = entry.get("name")
    if name not in REGISTRY:
        raise ConfigError(f"{source}: {where}.name: unknown algorithm {short(name)} (known: {', '.join(REGISTRY)})")
    _, model = REGISTRY[name]
    try:
        return label, model.model_validate(entry).model_dump(mode="json")
    except ValidationError as e:
        raise ConfigError(f"{source}: {where}.{_first_error(e)}") from None


def level_settings(base: dict[str, Any], level: Any, key: str) -> dict[str, Any]:
    """The raw settings of one factor level: a value for ``key``, or a mapping of dotted keys."""
    changes = level if isinstance(level, dict) else {key: level}
    out = base
    for k, v in changes.items():
        out = set_dotted(out, str(k), v)
    return out


def problem_dimensions(spec: ProblemSpec, where: str, source: str) -> list[tuple[int, str, dict[str, Any]]]:
    """``(dimension, problem name, params)`` for each dimension of a problem entry, each built once."""
    name, params = resolve_problem_name(spec.name, spec.params)
    wanted = spec.dimensions or [None]
    out = []
    for d in wanted:
        p = dict(params) if d is None else {**params, "n_var": d}
        try:
            problem = make_problem(name, p)
            build_space(problem, spec.bits, spec.gray, spec.variables)
        except ValueError as e:
            message = str(e)
            if d is not None and "n_var" in message:
                message = f"dimensions: problem {spec.name!r} does not take n_var (its dimension is fixed)"
            elif message.startswith("unknown problem"):
                message = message.rstrip(")") + ", or bbob-f1 .. bbob-f24)"
            raise ConfigError(f"{source}: {where}: {message}") from None
        out.append((int(problem.n_var), name, p))
    return out


def parse_study(data: dict[str, Any], source: str = "<study>") -> StudyConfig:
    try:
        study = StudyConfig.model_validate(data)
    except ValidationError as e:
        raise ConfigError(f"{source}: {_first_error(e)}") from None
    labels = [algorithm_settings(a, f"algorithms[{i}]", source)[0] for i, a in enumerate(study.algorithms)]
    for i, entry in enumerate(study.algorithms):  # a missing extra stops the study before any cell
        extra = getattr(REGISTRY[entry["name"]][0], "extra", None)
        if extra is not None:
            try:
                require(*extra)
            except EvoplanError as e:
                raise ConfigError(f"{source}: algorithms[{i}] ({labels[i]}): {e}") from None
    _unique(labels, "algorithms", "label", source)
    _unique([p.label or p.name for p in study.problems], "problems", "label", source)
    if study.factors is not None and study.factors.algorithm not in labels:
        raise ConfigError(f"{source}: factors.algorithm: no algorithm labelled {study.factors.algorithm!r} "
                          f"(labels: {', '.join(labels)})")
    n_variants = len(labels) + (sum(map(len, study.factors.vary.values())) - 1 if study.factors else 0)
    cells = sum(len(p.dimensions or [1]) for p in study.problems) * n_variants * study.seeds
    if cells > MAX_CELLS:
        raise ConfigError(f"{source}: seeds: {study.seeds} repetitions make {cells:.3g} runs, "
                          f"more than the {MAX_CELLS:,} a study may hold")
    reference = study.statistics.reference
    if reference is not None and reference not in labels:
        raise ConfigError(f"{source}: statistics.reference: no algorithm labelled {reference!r} "
                          f"(labels: {', '.join(labels)})")
    return study


def _unique(labels: list[str], key: str, what: str, source: str) -> None:
    seen = set()
    for i, label in enumerate(labels):
        if label in seen:
            raise ConfigError(f"{source}: {key}[{i}]: {what} {label!r} is used twice: give each entry its own label")
        seen.add(label)


def load_study(path: str | Path) -> StudyConfig:
    """Read and validate a study file; ``name`` defaults to the file's stem."""
    data = read_yaml(path)
    data.setdefault("name", Path(path).stem)
    return parse_study(data, str(path))
