"""A study's grid: one :class:`Cell` per (problem, dimension, algorithm, factor level, seed).

Each cell holds the complete settings of its run (``run``: the layout of a run file), so a
worker needs nothing else, and the cell's ``fingerprint`` tells whether a result already in the
results folder was made by these very settings.

Seeds (common random numbers): the seed of a run is drawn from
``SeedSequence(study seed, spawn_key=(crc32(problem label), dimension, repetition))``. It does
not depend on the algorithm or the factor level, so on one problem the r-th run of every
algorithm and level shares a seed: evoplan's GA and VEGA start from the same initial population,
and results are paired by repetition (hence the signed-rank test, see ``statistics.py``). It
does not depend on the order of the grid or on the backend either, so adding an algorithm or a
problem to a study leaves the other cells' seeds, and results, unchanged.
"""

from __future__ import annotations

import json
import re
import zlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ConfigError
from .config import StudyConfig, algorithm_settings, level_settings, problem_dimensions


@dataclass(frozen=True)
class Cell:
    """One run of the study; ``run`` is what a run file would hold."""

    key: str
    algorithm: str
    problem: str
    dimension: int
    factor: str
    level: str
    repetition: int
    seed: int
    budget: int | None
    run: dict[str, Any] = field(hash=False, compare=False)
    timeout_s: float | None = field(default=None, hash=False, compare=False)  # per evaluated row

    @property
    def fingerprint(self) -> str:
        return json.dumps(self.run, sort_keys=True)

    def labels(self) -> dict[str, Any]:
        return {"algorithm": self.algorithm, "problem": self.problem, "dimension": self.dimension,
                "factor": self.factor, "level": self.level, "repetition": self.repetition, "seed": self.seed}


def cell_seed(study_seed: int, problem: str, dimension: int, repetition: int) -> int:
    """The run seed of repetition ``repetition`` on ``problem`` in ``dimension`` (32 bits)."""
    ss = np.random.SeedSequence(study_seed, spawn_key=(zlib.crc32(problem.encode()), dimension, repetition))
    return int(ss.generate_state(1, np.uint32)[0])


def _safe(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.=+-]+", "_", text)


def _level_text(level: Any) -> str:
    if isinstance(level, dict):
        return ",".join(f"{k}={v}" for k, v in level.items())
    return str(level)


def variants(study: StudyConfig, source: str) -> list[tuple[str, str, str, dict[str, Any]]]:
    """``(label, factor, level, settings)`` of every algorithm variant, every level validated."""
    out = []
    for i, entry in enumerate(study.algorithms):
        label, settings = algorithm_settings(entry, f"algorithms[{i}]", source)
        f = study.factors
        if f is None or f.algorithm != label:
            out.append((label, "", "", settings))
            continue
        raw = {k: v for k, v in entry.items() if k != "label"}
        for key, levels in f.vary.items():
            for j, level in enumerate(levels):
                where = f"factors.vary.{key}[{j}]"
                try:
                    changed = level_settings(raw, level, key)
                except ValueError as e:
                    raise ConfigError(f"{source}: {where}: {e}") from None
                _, resolved = algorithm_settings(changed, where, source)
                out.append((label, key, _level_text(level), resolved))
    return out


def build_grid(study: StudyConfig, source: str = "<study>") -> list[Cell]:
    """Every cell of the study, in a fixed order (problem, dimension, algorithm, level, repetition)."""
    algos = variants(study, source)
    budget = study.budget.model_dump(exclude={"per_dimension"})
    cells = []
    for i, spec in enumerate(study.problems):
        plabel = spec.label or spec.name
        for dim, name, params in problem_dimensions(spec, f"problems[{i}]", source):
            termination = dict(budget)
            if study.budget.per_dimension and termination["evaluations"] is not None:
                termination["evaluations"] *= dim
            problem = {"name": name, "params": params, "bits": spec.bits, "gray": spec.gray,
                       "variables": {k: v.model_dump() for k, v in spec.variables.items()},
                       "constraint_penalty": spec.constraint_penalty}
            for alabel, factor, level, settings in algos:
                for r in range(study.seeds):
                    seed = cell_seed(study.seed, plabel, dim, r)
                    tag = f"{factor}={level}" if factor else "base"
                    key = _safe(f"{plabel}.d{dim}.{alabel}.{tag}.r{r:03d}")
                    run = {"name": key, "seed": seed, "problem": problem, "algorithm": settings,
                           "termination": termination, "output": {"plot": False},
                           "cache": study.cache.model_dump(mode="json")}
                    cells.append(Cell(key, alabel, plabel, dim, factor, level, r, seed,
                                      termination["evaluations"], run, study.evaluation.timeout_s))
    keys = [c.key for c in cells]
    if len(set(keys)) != len(keys):
        twice = next(k for k in keys if keys.count(k) > 1)
        raise ConfigError(f"{source}: two cells would share the name {twice!r}: make the labels and levels distinct")
    return cells


def reference_levels(study: StudyConfig, source: str = "<study>") -> dict[str, str]:
    """For each factor, the level whose settings are the base entry's (the family's reference)."""
    f = study.factors
    if f is None:
        return {}
    entry = next(a for a in study.algorithms if str(a.get("label", a.get("name"))) == f.algorithm)
    _, base = algorithm_settings(entry, "factors", source)
    raw = {k: v for k, v in entry.items() if k != "label"}
    out = {}
    for key, levels in f.vary.items():
        texts = [_level_text(lv) for lv in levels]
        same = [t for lv, t in zip(levels, texts)
                if algorithm_settings(level_settings(raw, lv, key), "factors", source)[1] == base]
        out[key] = same[0] if same else texts[0]
    return out
