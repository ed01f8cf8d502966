"""``evoplan evaluate CONFIG --set name=value ...``: every criterion of one parameter set, as JSON.

The problem is the one of the run file CONFIG. Each variable of the problem must be given with
``--set``; a categorical variable takes one of its choices (``--set tool=6``). Values outside
their range are errors (exit 2). Besides the objective, everything the problem reports through
an optional ``criteria(X) -> {name: (n,) array}`` method is printed.

``--out DIR`` also writes ``criteria.json`` (the printed report) and the plan's own files
(``toolpath.apt``, the zone map, the CC pattern), and ``--post NAME`` its NC program
(``program.nc`` / ``.h`` / ``.mpf``), all or nothing.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import ConfigError, EvoplanError
from ..overrides import refuse_repeat
from ..safe_yaml import load_text, short
from . import COMMANDS

if TYPE_CHECKING:
    import numpy as np


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("evaluate", help=COMMANDS["evaluate"])
    p.add_argument("config", help="YAML run file whose problem is evaluated")
    p.add_argument("--set", dest="values", action="append", default=[], metavar="NAME=VALUE",
                   help="a variable's value (repeat for each variable)")
    p.add_argument("--out", help="also write criteria.json and the plan's files (toolpath.apt, the zone map) "
                                 "into this new folder")
    p.add_argument("--post", help="with --out: also the plan's NC program in this dialect (iso, fanuc, "
                                  "heidenhain, siemens; the 5-axis posts with the default table-table A/C machine)")
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
    import numpy as np

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
    import numpy as np

    from ..config import load_config
    from ..runner import prepare

    if args.post and not args.out:
        raise EvoplanError("--post: give --out DIR for the NC program")
    if args.out:
        from ..folder_writer import check_out

        check_out(Path(args.out))
    if args.post:
        from ..problems.toolpath.export.posts import POSTS

        if args.post not in POSTS:
            raise EvoplanError(f"--post {args.post!r}: unknown post (known: {', '.join(sorted(POSTS))})")
    values = parse_assignments(args.values)
    config = load_config(args.config)
    if args.post:
        _check_post(args.config, config, args.post, values)
    prepared = prepare(config, str(args.config))
    space = prepared.space
    X = phenotype(space, values)
    problem = prepared.evaluator.problem
    result = prepared.evaluator(X)
    report: dict[str, Any] = {"variables": space.named(X[0]), "objective": _plain(result.f[0])}
    if result.errors:
        report["error"] = result.errors[0]
    from ..problem_factory import surface_facts

    if facts := surface_facts(problem):
        report["surface"] = facts
    criteria = getattr(problem, "criteria", None)
    if callable(criteria):
        try:
            report["criteria"] = {k: _plain(np.asarray(v).reshape(-1)[0]) for k, v in criteria(X).items()}
        except ValueError as e:
            raise ConfigError(f"{args.config}: {e}") from None
    if args.out:
        files = {"criteria.json": json.dumps(report, indent=2).encode()}
        files.update(_plan_files(args, problem, X))
        from ..folder_writer import write_folder

        write_folder(Path(args.out), files)
    print(json.dumps(report, indent=2))
    return 0


def _check_post(path: str, config, post_name: str, values: dict) -> None:
    """What ``--post`` needs of the run file, refused before any planning: a 5-axis post for a
    5-axis plan (``machine``, default 5axis), and the feed of the plan's tool (its ``feed``,
    else ``feed_rate``; a tools entry may leave it out for optimization runs, not for an NC
    program)."""
    from ..problems.toolpath.export.posts import POSTS

    params = config.problem.params
    if config.problem.name != "toolpath":
        return
    if not POSTS[post_name].five_axis and params.get("machine", "5axis") == "5axis":
        others = ", ".join(sorted(name for name, c in POSTS.items() if c.five_axis))
        raise ConfigError(f"{path}: problem.params.machine: --post {post_name} is a 3-axis post and the plan is "
                          f"5-axis (machine: 5axis): use a 5-axis post ({others}) or machine: 3axis")
    if "feed_rate" in params:
        return
    tools = params.get("tools")
    if not isinstance(tools, list):
        raise ConfigError(f"{path}: problem.params.feed_rate: missing (--post writes an NC program and the "
                          "default tools have no feed: give feed_rate, mm/min, or tools with their feed)")
    for i in _plan_tools(tools, values, params):
        if isinstance(tools[i], dict) and tools[i].get("feed") is None:
            raise ConfigError(f"{path}: problem.params.tools[{i}].feed: missing (--post writes an NC program: "
                              "give the tool its feed, mm/min, or problem.params.feed_rate)")


def _plan_tools(tools: list, values: dict, params: dict) -> list[int]:
    """Positions in ``tools`` of the tool the plan uses (``--set tool=ID``, ``fixed: {tool:
    ID}``, or the only one); every position when that is not known here."""
    fixed = params.get("fixed")
    tool_id = values.get("tool", fixed.get("tool") if isinstance(fixed, dict) else None)
    ids = [t.get("id", i + 1) if isinstance(t, dict) else None for i, t in enumerate(tools)]
    hits = [i for i, x in enumerate(ids) if tool_id is not None and str(x) == str(tool_id)]
    return hits or list(range(len(tools)))


def _plan_files(args, problem, X) -> dict[str, bytes]:
    """The plan's own files (``problem.artifacts``: toolpath.apt, the zone map, ...) and with
    ``--post`` its NC program; ConfigError (nothing written) if the post cannot write it."""
    artifacts = getattr(problem, "artifacts", None)
    if not callable(artifacts):
        if args.post:
            raise ConfigError(f"{args.config}: --post: the problem makes no toolpath")
        return {}
    try:
        files = dict(artifacts(X[0]))
        if args.post:
            files[f"program{_post_ext(args.post)}"] = _nc_program(problem, X, args.post)
    except ValueError as e:
        raise ConfigError(f"{args.config}: --post {args.post}: {str(e).splitlines()[0]}") from None
    return files


def _post_ext(name: str) -> str:
    from ..problems.toolpath.export.posts import POSTS

    return POSTS[name].extension


def _nc_program(problem, X, post_name: str) -> bytes:
    """The NC program of the plan of row X[0] (the tool numbered by its id)."""
    from ..problems.toolpath.export.kinematics import Kinematics, Rotary
    from ..problems.toolpath.export.posts import POSTS, Machine
    from ..problems.toolpath.export.toolpath import Toolpath, surface_comment

    cls = POSTS[post_name]
    genes = problem.genes.decode(problem.check(X))
    path = problem.planner.cl_path(genes, problem.programmed_feed(genes))
    tool = problem.tool_db.tools[int(genes["tool"][0])]
    tp = Toolpath.from_sections("finish", tool, path.tip, path.axis, path.section,
                                feed=path.feed_rate, plunge_feed=tool.plunge_feed,
                                comments=[surface_comment(problem.surface, problem.spec.surface)])
    if not cls.five_axis and tp.multi_axis:
        raise ValueError(f"{post_name} is a 3-axis post and the plan is 5-axis (use fanuc, heidenhain or siemens)")
    kin = Kinematics("table_table", Rotary("A", "x", (-30.0, 110.0)), Rotary("C", "z", (-360.0, 360.0)))
    return cls(Machine(kin if cls.five_axis else None)).program(tp).encode()


def _plain(value: Any) -> Any:
    import numpy as np

    value = np.asarray(value).item()
    return None if isinstance(value, float) and not np.isfinite(value) else value
