"""``evoplan machine CONFIG --out DIR [--set KEY.PATH=VALUE] [--from-run RUN]``: the NC operation set for one surface.

Roughing from a block (Abbas' morphing layers or z-level, flat end mill, zig-zag, checked on a
stock Z-map), semi-finish (ball end on the exact normal offset, 3-axis) and finish (the
evoplan toolpath problem's plan, its parameters from the file or from a finished run's
``best.json`` with ``--from-run``; or a 3-axis ball on the offset). Writes ``roughing``,
``semifinish`` and ``finish`` programs in the post's dialect (``.nc``; Heidenhain ``.h``,
Siemens ``.mpf``), the matching ``.apt`` files,
``surface.dxf``, ``surface.stl``, ``toolpaths.dxf``, ``layers.png`` and ``summary.json``
(layers, lengths, times, NC sizes). See ``runs/abbas_gentle.yaml``. Nothing is written unless
every operation and every post succeeds.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ConfigError, EvoplanError
from ..folder_writer import check_out, write_folder
from . import COMMANDS

if TYPE_CHECKING:
    from .machine_config import MachineConfig

def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("machine", help=COMMANDS["machine"])
    p.add_argument("config", help="YAML machining file (e.g. runs/abbas_gentle.yaml)")
    p.add_argument("--out", help="results folder (default: results/<name>-<time>)")
    from ..overrides import add_argument

    add_argument(p, "--set roughing.max_depth=1.5 --set finish.params.stepover=25")
    p.add_argument("--from-run", dest="from_run", help="a finished toolpath run: finish with its best plan")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.add_argument("--check", action="store_true",
                   help="read every 5-axis program back and verify the safety rules (clearance plane "
                        "for rotary turns and at the end, no table turn near the pole); one line, exit 2 "
                        "and nothing written if one fails")
    return p


def load(path: str, settings: list[str] = ()) -> MachineConfig:
    """The machining file ``path`` with the ``--set`` items applied, validated."""
    from pydantic import ValidationError

    from ..config import format_validation_error, read_yaml
    from ..overrides import apply_settings
    from ..problems.toolpath.spec.errors import HERE
    from .machine_config import MachineConfig

    data = apply_settings(read_yaml(path), list(settings), str(path))
    data.setdefault("name", Path(path).stem)
    try:
        return MachineConfig.model_validate(data)
    except ValidationError as e:
        first = e.errors()[0]
        msg = first["msg"].removeprefix("Value error, ")
        if HERE in msg:  # a check that names what is wrong itself (machine_config.py)
            from ..problems.toolpath.spec.errors import key_path

            raise ConfigError(f"{path}: {msg.replace(HERE, key_path(first['loc']))}".splitlines()[0]) from None
        raise ConfigError(format_validation_error(e, str(path))) from None


def plan_from_run(run: Path) -> tuple[dict, dict]:
    """(variables, toolpath problem params) of a finished run folder, read as data
    (:mod:`evoplan.run_folder`); ConfigError if unusable."""
    from ..problem_factory import REMOVED
    from ..run_folder import read_run_folder

    folder = read_run_folder(run, option="--from-run", can_trust=False)
    try:
        problem = folder.problem
        params = dict(problem.get("params", {}) or {})
        if problem.get("name") in REMOVED:
            raise ValueError(REMOVED[problem.get("name")])
        if problem.get("name", "toolpath") != "toolpath":
            raise ValueError(f"problem {problem.get('name')!r} is not a toolpath problem")
        variables = dict(folder.best["variables"])
        return variables, {k: v for k, v in params.items() if v is not None}
    except (ValueError, KeyError, TypeError, AttributeError) as e:
        raise ConfigError(f"{run}: --from-run: not a finished toolpath run ({str(e).splitlines()[0]})") from None


def main(args: argparse.Namespace) -> int:
    from ..extras import require
    from ..limits import available_bytes
    from ..problems.toolpath.roughing.operation_set import build_operations

    require("ezdxf", "exchange", "evoplan machine (surface.dxf, toolpaths.dxf)")
    require("stl", "exchange", "evoplan machine (surface.stl)")
    cfg = load(args.config, getattr(args, "settings", []))
    out = Path(args.out or Path("results") / f"{cfg.name}-{time.strftime('%Y%m%d-%H%M%S')}")
    check_out(out)
    plan = plan_from_run(Path(args.from_run)) if args.from_run else None
    from .progress import Stages

    with Stages("machine", 7, getattr(args, "quiet", False)) as stage:
        try:
            files, summary = build_operations(cfg.model_dump(), Path(args.config).resolve().parent, plan,
                                              max_bytes=available_bytes(), progress=stage)
            stage.finish()
        except ValueError as e:
            raise ConfigError(f"{args.config}: {e}") from None
    if args.check:
        failed = {op: s["safety"]["violations"] for op, s in summary.items()
                  if isinstance(s, dict) and s.get("safety") and s["safety"]["violations"]}
        if failed:
            op, v = next(iter(failed.items()))
            raise EvoplanError(f"{args.config}: --check: {summary[op]['nc_file']} breaks {len(v)} safety rule(s), "
                               f"first: {v[0]}")
    write_folder(out, files)  # all files or none (a full disk: one line)
    record = {"out": str(out), **{op: {k: summary[op][k] for k in ("nc_file", "time_min", "nc_bytes")}
                                  for op in ("roughing", "semifinish", "finish")}}
    if args.check:  # what was verified: each 5-axis program's rules held
        record["check"] = {op: {"ok": True, "repositions": s["safety"]["repositions"],
                                "c_travel_deg": round(s["safety"]["c_travel"], 1),
                                "c_travel_near_pole_deg": round(s["safety"]["c_travel_pole"], 1)}
                           for op, s in summary.items() if isinstance(s, dict) and s.get("safety")}
    print(json.dumps(record))
    return 0
