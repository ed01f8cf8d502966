"""``evoplan simulate``: cut a toolpath in simulation and measure what it leaves on the part.

Three ways to name the toolpath, over the surface of a run file's toolpath problem:

    evoplan simulate CONFIG --set tool=6 --set stepover=41.729 ... [--out DIR]   # a parameter set
    evoplan simulate --run DIR [--out DIR2]                       # the best plan of a finished run
                                        # (read as data: a run of user code needs --trust-code MODULE)
    evoplan simulate CONFIG --apt FILE [--out DIR]                # an outside APT CL file
    evoplan simulate CONFIG --nc FILE --tool [TYPE:]D[,r][,NAME=VALUE...] [--out DIR]
                                                  # an outside ISO/Fanuc program, with its cutter

Writes ``simulation.json`` (scallop max / mean / p50 / p90 / p99, gouge max and area, uncut
fraction, grid, CL points, seconds, per-zone figures), ``deviation_map.png``,
``deviation_hist.png``, ``deviation.npz`` and, for a plan (``--set`` or ``--run``), its
``toolpath.apt`` into the folder, all or nothing, and prints the JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

from ..errors import ConfigError, EvoplanError
from .evaluate import parse_assignments
from . import COMMANDS


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("simulate", help=COMMANDS["simulate"])
    p.add_argument("config", nargs="?", help="YAML run file whose toolpath problem gives the surface")
    src = p.add_mutually_exclusive_group()
    src.add_argument("--set", dest="values", action="append", default=[], metavar="NAME=VALUE",
                     help="a parameter of the plan (repeat for each)")
    src.add_argument("--run", help="a finished run's results folder: simulate its best plan")
    p.add_argument("--trust-code", dest="trust_code", metavar="MODULE",
                   help="with --run: allow the folder's problem to import MODULE (user code); "
                        "without it a results folder runs no code")
    src.add_argument("--apt", help="an APT CL file (GOTO/x,y,z[,i,j,k], CUTTER/, MULTAX)")
    src.add_argument("--nc", help="an ISO/Fanuc G-code program (G0-G3, G17-19, G90/91, G43.4 with A/C "
                                  "of a table-table machine); needs --tool")
    p.add_argument("--tool", metavar="[TYPE:]D[,r][,NAME=VALUE...]",
                   help="with --nc: the cutter, any registered type (ball, flat, toroidal, "
                        "tapered_ball...; without one, r says: 0 flat, D/2 ball, else toroidal), "
                        "its diameter D and corner radius r (mm), then its own parameters by "
                        "name: 12,6 | 12 | toroidal:16,3 | tapered_ball:8,1,taper_angle=10")
    p.add_argument("--out", help="folder for simulation.json, the figures and, for a plan, its toolpath.apt "
                                 "(default: results/simulate-<time>)")
    p.add_argument("--grid", type=float, default=0.1, metavar="MM", help="cell size (default 0.1 mm)")
    p.add_argument("--rays", choices=["normal", "vertical"], default="normal",
                   help="measure along the design-surface normal (default) or vertically")
    p.add_argument("--tolerance", type=float, metavar="MM",
                   help="tolerance band of the map (default: the problem's tolerance or h_c)")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.add_argument("--allowance", type=float, default=0.5, metavar="MM",
                   help="finishing stock left where no pose reaches (default 0.5 mm)")
    return p


def _memory_limit() -> float:
    """Half the machine's memory: a grid above it is refused before it is allocated."""
    try:
        return 0.5 * os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return 8.0 * 2**30


def _problem_and_plan(args):
    from ..config import parse_config
    from ..run_folder import read_run_folder
    from ..runner import prepare, prepare_file

    if args.run:
        folder = read_run_folder(args.run, args.trust_code)
        config = str(folder.config_path)
        params = folder.best.get("variables")
        if not isinstance(params, dict):
            raise ConfigError(f"{folder.path / 'best.json'}: variables: the run has no best solution")
        data = dict(folder.config)
        data.setdefault("name", folder.path.name)
        prepared = prepare(parse_config(data, config), config)
    else:
        if not args.config:
            raise EvoplanError("simulate: give a run file CONFIG (with --set or --apt), or --run DIR")
        config, params = args.config, None
        prepared = prepare_file(config)
    problem = prepared.evaluator.problem
    if not callable(getattr(problem, "cl_path", None)):
        raise ConfigError(f"{config}: problem: {prepared.config.problem.name!r} makes no toolpath "
                          "to simulate (use a toolpath problem)")
    if args.apt:
        from ..problems.toolpath.export.apt_read import AptError, read_apt
        from ..problems.toolpath.clpath import CLPath

        try:
            apt = read_apt(args.apt)
            path = CLPath.from_apt(apt)
        except AptError as e:
            raise ConfigError(f"{args.apt}: {e}") from None
        except (OSError, ValueError) as e:
            raise ConfigError(f"{args.apt}: {e}") from None
        return config, problem, path, None, f"APT file {Path(args.apt).name}", _read_facts(apt), {}
    if getattr(args, "nc", None):
        return (config, problem, *_nc_path(args))
    if params is None:
        if not args.values:
            raise EvoplanError(f"{config}: give the plan's parameters with --set NAME=VALUE, "
                               "or --run DIR, or --apt FILE")
        params = parse_assignments(args.values)
    try:
        path, labels = problem.cl_path(params)
    except ValueError as e:
        raise ConfigError(f"{config}: {e}") from None
    label = ", ".join(f"{k} {v:g}" if isinstance(v, float) else f"{k} {v}" for k, v in params.items())
    return config, problem, path, labels, label, {}, _plan_apt(problem, params, path, label)


def _plan_apt(problem, params: dict, path, label: str) -> dict[str, bytes]:
    """``toolpath.apt``: the plan simulated as a CL file (its tool from the problem's tools)."""
    import textwrap

    from ..problems.toolpath.export.apt_write import apt_plan
    from ..problems.toolpath.export.toolpath import surface_comment

    tool_db, genes = getattr(problem, "tool_db", None), getattr(problem, "genes", None)
    if tool_db is None or genes is None:  # a problem of user code without a tool database
        return {}
    tool = tool_db.tools[int(genes.decode(problem.row(params))["tool"][0])]
    comments = textwrap.wrap(f"evoplan simulate: {label}", 66)
    if getattr(problem, "surface", None) is not None:  # its type (a mesh: the fit's deviation)
        spec = getattr(getattr(problem, "spec", None), "surface", None)
        comments.append(surface_comment(problem.surface, spec))
    text = apt_plan(path, tool, comments=comments)
    return {"toolpath.apt": text.encode()}


def _read_facts(tp) -> dict:
    """What simulation.json says of a file read (an APT or NC program): the statements or
    words that were read but do not move the tool, counted (``ignored_statements``)."""
    return {"ignored_statements": dict(sorted((tp.ignored or {}).items()))}


def _nc_path(args):
    """(CLPath, None, label, facts, no files) of ``--nc FILE --tool [TYPE:]D[,r][,NAME=VALUE...]``."""
    from ..problems.toolpath.clpath import CLPath
    from ..problems.toolpath.export.gcode_read import GcodeError, read_gcode
    from ..problems.toolpath.export.kinematics import Kinematics, Rotary
    from ..problems.toolpath.spec.tools import tool_from_text

    try:
        cutter = tool_from_text(args.tool or "", "--tool").cutter
    except ValueError as e:
        raise ConfigError(str(e)) from None
    kin = Kinematics("table_table", Rotary("A", "x", (-120, 120)), Rotary("C", "z", (-1e6, 1e6)))
    try:
        # arcs as chords of 1 um: the cut is the arc, not a polygon 10 um inside it
        tp = read_gcode(args.nc, cutter, kin, chord_tol=1e-3)
        return CLPath.from_apt(tp), None, f"NC file {Path(args.nc).name}", _read_facts(tp), {}
    except (GcodeError, OSError, ValueError) as e:
        raise ConfigError(f"{args.nc}: {e}") from None


def main(args: argparse.Namespace) -> int:
    import numpy as np
    from tqdm import tqdm

    from ..folder_writer import check_out, write_folder

    for name in ("grid", "allowance") + (("tolerance",) if args.tolerance is not None else ()):
        value = getattr(args, name)
        if not (np.isfinite(value) and value > 0):
            raise EvoplanError(f"--{name} {value}: must be a positive number of mm")
    out = Path(args.out or Path("results") / f"simulate-{time.strftime('%Y%m%d-%H%M%S')}")
    check_out(out)
    stages = tqdm(total=4, desc="simulate", unit="stage", disable=True if args.quiet else None,
                  bar_format="{desc}: {n}/{total} {postfix} [{elapsed}]")
    try:
        record, files = _measure(args, stages)
        stages.update()
    finally:
        stages.close()
    write_folder(out, files)  # all files or none (a full disk: one line)
    print(json.dumps(record, indent=2))
    print(f"evoplan: simulation written to {out}", flush=True)
    return 0


def _measure(args: argparse.Namespace, stages) -> tuple[dict, dict[str, bytes]]:
    """The plan cut in simulation: (simulation.json record, the files' bytes), stage by stage."""
    from ..problems.toolpath.simulation import design_grid, simulate
    from ..problems.toolpath.simulation.figures import deviation_hist_png, deviation_map_png

    stages.set_postfix_str("plan")
    config, problem, path, labels, label, read_facts, plan_files = _problem_and_plan(args)
    tolerance = args.tolerance or float(getattr(problem, "simulation_tolerance", 0.01))
    t0 = time.perf_counter()
    try:
        stages.update()
        stages.set_postfix_str(f"design grid {args.grid:g} mm")
        grid = design_grid(problem.surface, args.grid, max_bytes=_memory_limit())
        stages.update()
        stages.set_postfix_str(f"sweep of {len(path.tip)} CL points over {grid.z.size} cells")
        sim = simulate(path, grid, vertical=args.rays == "vertical", allowance=args.allowance,
                       mesh_labels=labels)
    except ValueError as e:
        raise ConfigError(f"{args.apt or config}: {e}") from None
    seconds = time.perf_counter() - t0
    stages.update()
    stages.set_postfix_str("figures")
    from ..problem_factory import surface_facts

    record = {"plan": label, **read_facts, **sim.summary(path, seconds)}
    if facts := surface_facts(problem):
        record["surface"] = facts  # a mesh: the fit the plan was made on, and its deviation
    title = f"{label}\nscallop max {sim.metrics['scallop_max_mm']:.4f} mm, p99 " \
            f"{sim.metrics['scallop_p99_mm']:.4f} mm, gouge max {sim.metrics['gouge_max_mm']:.4f} mm"
    files = {
        "simulation.json": (json.dumps(record, indent=2) + "\n").encode(),
        "deviation_map.png": deviation_map_png(grid, sim.residual.values, tolerance=tolerance,
                                               allowance=args.allowance, labels=sim.labels,
                                               title=title),
        "deviation_hist.png": deviation_hist_png(grid, sim.residual.values, tolerance=tolerance,
                                                 allowance=args.allowance),
        "deviation.npz": _deviation_npz(grid, sim, path, tolerance, args.allowance),
        **plan_files,
    }
    return record, files


def _deviation_npz(grid, sim, path, tolerance: float, allowance: float) -> bytes:
    """The deviation map as data for ``evoplan report`` (float32 heights and deviations, compressed)."""
    import io

    import numpy as np

    buf = io.BytesIO()
    labels = sim.labels if sim.labels is not None else np.zeros(grid.shape, np.int16)
    np.savez_compressed(buf, x0=grid.x0, y0=grid.y0, h=grid.h, z=grid.z.astype(np.float32),
                        inside=grid.inside, residual=sim.residual.values.astype(np.float32),
                        labels=np.asarray(labels, np.int16), tolerance=tolerance, allowance=allowance,
                        tip=path.tip, axis=path.axis, section=path.section, zone=path.zone)
    return buf.getvalue()
