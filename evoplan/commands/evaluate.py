"""``evoplan evaluate CONFIG --set name=value ...``: every criterion of one parameter set, as JSON.

The problem is the one of the run file CONFIG. Each variable of the problem must be given with
``--set``; a categorical variable takes one of its choices (``--set tool=6``). Values outside
their range are errors (exit 2). Besides the objective, everything the problem reports through
an optional ``criteria(X) -> {name: (n,) array}`` method is printed.
"""

from __future__ import annotations

import argparse
import json
from typing import Any

import numpy as np

from ..errors import ConfigError, EvoplanError
from ..overrides import refuse_repeat
from ..safe_yaml import load_text, short
from . import COMMANDS


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("evaluate", help=COMMANDS["evaluate"])
    p.add_argument("config", help="YAML run file whose problem is evaluated")
    p.add_argument("--set", dest="values", action="append", default=[], metavar="NAME=VALUE",
                   help="a variable's value (repeat for each variable)")
    return p


def parse_assignments(items: list[str]) -> dict[str, Any]:
    values: dict[str, Any] = {}
    seen: dict[str, str] = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep or not name.strip():
            raise EvoplanError(f"--set {item!r}: expected NAME=VALUE")
        refuse_repeat(seen, name.strip(), text)
        values[name.strip()] = load_text(text, f"--set {short(item)}") if text.strip() else text
    return values


def phenotype(space, values: dict[str, Any]) -> np.ndarray:
    """The row ``X: (1, d)`` of named values; choices become their index. One-line errors."""
    unknown = sorted(set(values) - set(space.names))
    if unknown:
        raise EvoplanError(f"--set {unknown[0]}: no such variable (the problem has {', '.join(space.names)})")
    missing = [n for n in space.names if n not in values]
    if missing:
        raise EvoplanError(f"missing --set for: {', '.join(missing)}")
    row = []
    for v in space.variables:
        value = values[v.name]
        if v.kind == "categorical":
            matches = [i for i, c in enumerate(v.choices) if c == value or str(c) == str(value)]
            if not matches:
                raise EvoplanError(f"--set {v.name}={value!r}: not one of {list(v.choices)}")
            row.append(float(matches[0]))
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise EvoplanError(f"--set {v.name}={value!r}: expected a number")
        if not v.low <= value <= v.high:
            raise EvoplanError(f"--set {v.name}={value}: outside its range [{v.low}, {v.high}]")
        if v.kind == "integer" and value != int(value):
            raise EvoplanError(f"--set {v.name}={value}: expected an integer")
        row.append(float(value))
    return np.array([row])


def main(args: argparse.Namespace) -> int:
    from ..runner import prepare_file

    prepared = prepare_file(args.config)
    space = prepared.space
    X = phenotype(space, parse_assignments(args.values))
    problem = prepared.evaluator.problem
    result = prepared.evaluator(X)
    report: dict[str, Any] = {"variables": space.named(X[0]), "objective": _plain(result.f[0])}
    if result.errors:
        report["error"] = result.errors[0]
    criteria = getattr(problem, "criteria", None)
    if callable(criteria):
        try:
            report["criteria"] = {k: _plain(np.asarray(v).reshape(-1)[0]) for k, v in criteria(X).items()}
        except ValueError as e:
            raise ConfigError(f"{args.config}: {e}") from None
    print(json.dumps(report, indent=2))
    return 0


def _plain(value: Any) -> Any:
    value = np.asarray(value).item()
    return None if isinstance(value, float) and not np.isfinite(value) else value
