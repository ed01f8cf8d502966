"""YAML run configuration, validated once at the edge (pydantic models, unknown keys rejected).

Layout of a run file::

    name: kubota_vega            # optional, defaults to the file name
    seed: 1
    problem: {name: kubota, params: {}, bits: 23, gray: false, variables: {x1: {bits: 20}}}
    algorithm: {name: vega, population: 20, ..., virus: {count: 7, ...}}   # or ga, pymoo_de, ...
    termination: {generations: 50, evaluations: null, target: null, seconds: null}
    checkpoint: {every_generations: null, every_seconds: 30}
    evaluation: {backend: serial, workers: null, scheduler: null, chunks: null}
    output: {plot: true}

Every error names the file, the key path and the problem, on one line.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from .adapters import ADAPTERS
from .algorithms import ALGORITHMS
from .cache import CacheConfig
from .errors import ConfigError
from .safe_yaml import key_text, load_file, short


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)  # .inf/.nan: no setting means them


class VariableOverride(_Strict):
    """Per-variable override of the bounds a problem declares, and of the bit count."""

    low: float | None = None
    high: float | None = None
    bits: int | None = Field(None, ge=1, le=52)

    @model_validator(mode="after")
    def _ordered(self):
        if self.low is not None and self.high is not None and self.low >= self.high:
            raise ValueError(f"lower bound {self.low} must be below upper bound {self.high}")
        return self


class ProblemConfig(_Strict):
    name: str
    params: dict[str, Any] = Field(default_factory=dict)
    bits: int = Field(23, ge=1, le=52, description="bits per real variable (Fountas: 46 for 2)")
    gray: bool = False
    variables: dict[str, VariableOverride] = Field(default_factory=dict)
    constraint_penalty: float = Field(1e6, ge=0)


class TerminationConfig(_Strict):
    generations: int | None = Field(None, ge=1)
    evaluations: int | None = Field(None, ge=1)
    target: float | None = None
    seconds: float | None = Field(None, gt=0)

    @model_validator(mode="after")
    def _at_least_one(self):
        if all(v is None for v in (self.generations, self.evaluations, self.target, self.seconds)):
            raise ValueError("give at least one of generations, evaluations, target, seconds")
        if self.generations is None and self.evaluations is None and self.seconds is None:
            raise ValueError("a target alone may never be reached: add generations, evaluations or seconds")
        return self


class CheckpointConfig(_Strict):
    every_generations: int | None = Field(None, ge=1)
    every_seconds: float | None = Field(30.0, gt=0)


class OutputConfig(_Strict):
    plot: bool = True


class EvaluationConfig(_Strict):
    """Where one population's evaluations run: here, local processes, or Dask workers.

    For expensive black boxes (a CAM system, a slow simulator); a cheap vectorized problem is
    fastest ``serial``. The numbers are the same on every backend.
    """

    backend: Literal["serial", "processes", "dask"] = "serial"
    workers: int | None = Field(None, ge=1)
    scheduler: str | None = Field(None, description="address of a running Dask scheduler")
    chunks: int | None = Field(None, ge=1, description="pieces a batch is cut into (default: one per worker)")
    timeout_s: float | None = Field(None, gt=0, description="a chunk running longer fails its rows (processes, dask)")

    @model_validator(mode="after")
    def _scheduler_needs_dask(self):
        if self.scheduler and self.backend != "dask":
            raise ValueError(f"a scheduler is for backend dask, not {self.backend}")
        if self.timeout_s is not None and self.backend == "serial":
            raise ValueError("timeout_s needs backend processes or dask (a serial evaluation cannot be stopped)")
        return self


# every algorithm a run or a study can name: name -> (class, settings model)
REGISTRY: dict[str, tuple[type, type]] = {**ALGORITHMS, **ADAPTERS}

AlgorithmConfig = Annotated[Union[tuple(model for _, model in REGISTRY.values())], Field(discriminator="name")]


# a run's name becomes part of its default results folder: one plain file name (no path
# separator, control character or leading dot), short enough for any file system
SafeName = Annotated[str, Field(max_length=120, pattern=r"^[^/\\.\x00-\x1f][^/\\\x00-\x1f]*$")]


class RunConfig(_Strict):
    name: SafeName | None = None
    seed: int = Field(0, ge=0)
    problem: ProblemConfig
    algorithm: AlgorithmConfig
    termination: TerminationConfig
    checkpoint: CheckpointConfig = CheckpointConfig()
    evaluation: EvaluationConfig = EvaluationConfig()
    output: OutputConfig = OutputConfig()
    cache: CacheConfig = CacheConfig()  # evaluation cache and what the budget counts (evoplan/cache.py)

    def resolved(self) -> dict[str, Any]:
        """Every setting, defaults included, as plain data (what ``config.yaml`` records)."""
        return self.model_dump(mode="json")

    def fingerprint(self) -> dict[str, Any]:
        """The settings that decide a run's numbers (a run may resume on another backend)."""
        return {k: v for k, v in self.resolved().items() if k != "evaluation"}


def read_yaml(path: str | Path) -> dict[str, Any]:
    """A YAML mapping from ``path``, read with limits (:mod:`evoplan.safe_yaml`): one-line errors."""
    data = load_file(path)
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: expected a mapping of settings at the top level")
    return data


def format_validation_error(error: ValidationError, source: str) -> str:
    """The first error of a pydantic validation as ``source: key.path: message (got value)``."""
    first = error.errors()[0]
    loc = [key_text(p) for p in first["loc"]]
    if len(loc) > 1 and loc[0] == "algorithm" and first["type"] != "union_tag_invalid":
        del loc[1]  # the discriminator tag pydantic inserts ("algorithm.vega.virus...")
    got = first.get("input")
    if first["type"] == "union_tag_invalid":
        loc.append("name")
        msg = f"unknown algorithm {short(first['ctx']['tag'])} (known: {first['ctx']['expected_tags']})"
    elif first["type"] == "union_tag_not_found":
        loc.append("name")
        msg = f"missing (known: {', '.join(REGISTRY)})"
    elif first["type"] == "missing":
        msg = "missing"
    elif first["type"] == "string_pattern_mismatch" and loc[-1:] == ["name"]:
        msg = f"must be a plain file name: no '/', '\\', control character or leading '.' (got {short(got)})"
    else:
        msg = first["msg"].removeprefix("Value error, ")
        if not isinstance(got, dict):
            msg += f" (got {short(got)})"
    more = len(error.errors()) - 1
    tail = f" [+{more} more error{'s' if more > 1 else ''}]" if more else ""
    return f"{source}: {'.'.join(loc) or '(top level)'}: {msg}{tail}"


def parse_config(data: dict[str, Any], source: str = "<config>") -> RunConfig:
    try:
        return RunConfig.model_validate(data)
    except ValidationError as e:
        raise ConfigError(format_validation_error(e, source)) from None


def load_config(path: str | Path, seed: int | None = None) -> RunConfig:
    """Read and validate a run file; ``seed`` overrides the file's seed; ``name`` defaults to the stem."""
    data = read_yaml(path)
    if seed is not None:
        data["seed"] = seed
    data.setdefault("name", Path(path).stem)
    return parse_config(data, str(path))
