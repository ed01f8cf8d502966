"""``evoplan machine CONFIG --out DIR [--set KEY.PATH=VALUE] [--from-run RUN]``: the NC operation set for one surface.

Roughing from a block (Abbas' morphing layers or z-level, flat end mill, zig-zag, checked on a
stock Z-map), semi-finish (ball end on the exact normal offset, 3-axis) and finish (the
evoplan toolpath problem's plan, its parameters from the file or from a finished run's
``best.json`` with ``--from-run``; or a 3-axis ball on the offset). Writes ``roughing.nc``,
``semifinish.nc``, ``finish.nc`` in the post's dialect, the matching ``.apt`` files,
``surface.dxf``, ``surface.stl``, ``toolpaths.dxf``, ``layers.png`` and ``summary.json``
(layers, lengths, times, NC sizes). See ``runs/abbas_gentle.yaml``. Nothing is written unless
every operation and every post succeeds.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any, Literal

from pydantic import Field, ValidationError

from ..config import _Strict, format_validation_error, read_yaml
from ..errors import ConfigError, EvoplanError
from ..folder_writer import check_out, write_folder
from ..limits import available_bytes
from . import COMMANDS


class ToolCfg(_Strict):
    number: int = Field(1, ge=0)
    diameter: float = Field(12.0, gt=0)
    spindle: float = Field(6000.0, gt=0)


class StockCfg(_Strict):
    top: float | None = None          # absolute; default z_max + top_offset
    top_offset: float = Field(5.0, ge=0)
    cell: float = Field(0.5, gt=0)    # Z-map and layer grid, mm


class AllowanceCfg(_Strict):
    semifinish: float = Field(0.5, ge=0)   # D_off1
    finish: float = Field(0.3, ge=0)       # D_off2


class RoughCfg(_Strict):
    method: Literal["morphing", "morphing_full", "zlevel", "contour"] = "morphing"
    tool: ToolCfg = Field(default_factory=lambda: ToolCfg(number=1, diameter=12.0, spindle=6000.0))
    max_depth: float = 2.0             # D_cut, mm
    stepover: float = Field(0.6, gt=0, le=1)   # fraction of the diameter
    feed: float = Field(800.0, gt=0)
    plunge_feed: float = Field(250.0, gt=0)
    tolerance: float = Field(0.01, gt=0)


class BallCfg(_Strict):
    tool: ToolCfg = Field(default_factory=lambda: ToolCfg(number=2, diameter=12.0, spindle=8000.0))
    stepover: float = Field(1.5, gt=0)  # mm between passes
    step: float = Field(1.0, gt=0)      # mm between points
    feed: float = Field(1000.0, gt=0)
    plunge_feed: float = Field(300.0, gt=0)


class PlanParams(_Strict):
    tool: int = 8
    stepover: float = 30.0
    lead: float = 2.0
    tilt: float = 0.0
    step: float = 6.0


class FinishCfg(BallCfg):
    source: Literal["plan", "offset"] = "plan"
    params: PlanParams = Field(default_factory=PlanParams)
    problem: dict[str, Any] = Field(default_factory=dict)   # toolpath problem params (not surface)


class RotaryCfg(_Strict):
    name: str
    about: Literal["x", "y", "z"]
    limits: list[float] = Field(min_length=2, max_length=2)


class KinematicsCfg(_Strict):
    layout: Literal["table_table", "head_table"] = "table_table"
    tilt: RotaryCfg = Field(default_factory=lambda: RotaryCfg(name="A", about="x", limits=[-30.0, 110.0]))
    rotary: RotaryCfg = Field(default_factory=lambda: RotaryCfg(name="C", about="z", limits=[-360.0, 360.0]))
    max_step: float = Field(10.0, gt=0)        # degrees per NC block (larger turns are split)
    max_deviation: float = Field(5.0, gt=0)   # degrees off the great circle before a reposition
    clearance_height: float = Field(20.0, gt=0)   # clearance plane above the stock top, mm
    clearance_plane: float | None = None       # or the plane's absolute Z (at or above the stock top)
    rotary_threshold: float = Field(20.0, gt=0)   # larger rotary turns only at the clearance plane (deg)
    pole_angle: float = Field(0.5, ge=0, lt=90)   # |tilt| below which the table holds (deg; 0: off)
    rapid_rotary: float = Field(5400.0, gt=0)     # rotary rapid rate, deg/min


class PostCfg(_Strict):
    dialect: str = "fanuc"
    work_offset: str = Field("G54", pattern=r"^G5[4-9]$")
    program_number: int = Field(1000, ge=1, le=9999)
    rapid_rate: float = Field(10000.0, gt=0)
    tolerance: float | None = Field(None, gt=0)  # mm: merge near-collinear points, fit G2/G3 (iso); None: every point
    kinematics: KinematicsCfg = Field(default_factory=KinematicsCfg)


class MachineConfig(_Strict):
    name: str = "machine"
    surface: Any = "choi"
    stock: StockCfg = Field(default_factory=StockCfg)
    allowances: AllowanceCfg = Field(default_factory=AllowanceCfg)
    roughing: RoughCfg = Field(default_factory=RoughCfg)
    semifinish: BallCfg = Field(default_factory=BallCfg)
    finish: FinishCfg = Field(default_factory=lambda: FinishCfg(
        tool=ToolCfg(number=3, diameter=12.0, spindle=10000.0), stepover=0.8, step=0.5, feed=1200.0))
    post: PostCfg = Field(default_factory=PostCfg)


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
                        "for rotary turns and at the end, no table turn near the pole); exit 1 if one fails")
    return p


def load(path: str, settings: list[str] = ()) -> MachineConfig:
    """The machining file ``path`` with the ``--set`` items applied, validated."""
    from ..overrides import apply_settings

    data = apply_settings(read_yaml(path), list(settings), str(path))
    data.setdefault("name", Path(path).stem)
    try:
        return MachineConfig.model_validate(data)
    except ValidationError as e:
        raise ConfigError(format_validation_error(e, str(path))) from None


def plan_from_run(run: Path) -> tuple[dict, dict]:
    """(variables, toolpath problem params) of a finished run folder (a ``toolpath_zoning`` run's
    params translated to ``toolpath``'s), read as data (:mod:`evoplan.run_folder`); ConfigError
    if unusable."""
    from ..run_folder import read_run_folder

    folder = read_run_folder(run, option="--from-run", can_trust=False)
    try:
        problem = folder.problem
        params = dict(problem.get("params", {}) or {})
        if problem.get("name") == "toolpath_zoning":
            from ..problems.toolpath.zoned import zoning_config

            params = zoning_config(**params)
        elif problem.get("name", "toolpath") != "toolpath":
            raise ValueError(f"problem {problem.get('name')!r} is not a toolpath problem")
        variables = dict(folder.best["variables"])
        return variables, {k: v for k, v in params.items() if v is not None}
    except (ValueError, KeyError, TypeError, AttributeError) as e:
        raise ConfigError(f"{run}: --from-run: not a finished toolpath run ({str(e).splitlines()[0]})") from None


def main(args: argparse.Namespace) -> int:
    from ..extras import require
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
            raise EvoplanError(f"{args.config}: --check: {op}.nc breaks {len(v)} safety rule(s), first: {v[0]}")
    write_folder(out, files)  # all files or none (a full disk: one line)
    print(json.dumps({"out": str(out), **{op: {k: summary[op][k] for k in ("time_min", "nc_bytes")}
                                          for op in ("roughing", "semifinish", "finish")}}))
    return 0
