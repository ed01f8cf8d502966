"""``evoplan zone CONFIG [--out DIR] [--quiet]``: zone a surface, optimize each zone's feed direction.

The file names the surface, the tool (a run file's tools entry: any registered cutter, e.g.
``tool: {type: tapered_ball, diameter: 8, corner_radius: 1, taper_angle: 10}``; the older
``cutter: {R, r}`` still reads), the scallop limit h_c, the zone-change
penalty Delta L, the parametric mesh, the zoning method (any name of the registry in
``problems/toolpath/plan/zoning/methods/``: single, kmeans, amas) with a settings group per method,
and ``merge`` (the post-process of ``zoning/merge.py``); see ``runs/choi_zoning.yaml``. The
config model is built from the registry, so this command holds no method logic. The plan
is the one toolpath engine's (3-axis, drop-cutter placement, passes spaced for h_c, each
zone along its optimized direction), so its lengths are those of the sections it cuts.
``strategy`` (or ``--strategy NAME``) picks the pass layout of ``plan/strategies``
(default parallel). Writes ``summary.json`` (method, strategy, the cutter, zones, per-zone direction,
passes and length, total length of Djebali Eq. 4 with the edge runs, the lengths as the
papers count them: ``length_on_part_mm`` and ``length_papers_mm`` = on part + penalty,
penalty, merge counts, seconds), ``zones.csv`` (cell -> zone, with the cell's features),
``zone_map.png`` (the zones and the sections cut) and ``toolpath.apt`` (the CL path).
Nothing is written unless the whole plan succeeds. A progress line names each stage (zones,
passes, the files) on a terminal; ``--quiet`` silences it.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import ConfigError
from ..folder_writer import check_out, write_folder
from . import COMMANDS

if TYPE_CHECKING:
    from .zone_config import ZoneBase

# the registered zoning methods, named without importing the registry (scipy, scikit-learn,
# numba) so that ``evoplan zone --help`` starts at once; a test checks them against it
ZONING_METHODS = ("single", "kmeans", "amas")
STRATEGY_NAMES = ("parallel", "isoscallop", "contour", "isoparametric")


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("zone", help=COMMANDS["zone"])
    p.add_argument("config", help="YAML zoning file (e.g. runs/choi_zoning.yaml)")
    p.add_argument("--out", help="results folder (default: results/<name>-<time>)")
    p.add_argument("--method", metavar="NAME",
                   help=f"override the method (registered: {', '.join(ZONING_METHODS)})")
    p.add_argument("--strategy", metavar="NAME",
                   help=f"override the pass layout ({', '.join(STRATEGY_NAMES)})")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    return p


def load(path: str, method: str | None = None, strategy: str | None = None) -> ZoneBase:
    """The validated zoning file (``method`` / ``strategy``: the --method / --strategy
    overrides); ConfigError."""
    from pydantic import ValidationError

    from ..config import format_validation_error, read_yaml
    from ..limits import mesh_bytes, require
    from .zone_config import zone_config_model

    data = read_yaml(path)
    data.setdefault("name", Path(path).stem)
    if method is not None:
        data["method"] = method
    if strategy is not None:
        data["strategy"] = strategy
    older = data.get("cutter")
    if isinstance(older, dict) and set(older) - {"R", "r"}:  # a tools entry under the old key
        raise ConfigError(f"{path}: cutter.{sorted(set(older) - {'R', 'r'})[0]}: cutter holds "
                          f"only R and r; write any registered cutter as a run file's tools "
                          f"entry: tool: {{type, diameter, corner_radius, ...}}")
    try:
        cfg = zone_config_model().model_validate(data)
    except ValidationError as e:
        if e.errors()[0]["loc"][:1] == ("tool",):  # a tools entry: the run file's own lines
            from ..problems.toolpath.spec.errors import one_line
            from ..problems.toolpath.spec.tools import ToolSettings

            line = one_line(e, known_of=lambda loc: list(ToolSettings.model_fields)
                            if tuple(loc) == ("tool",) else None)
            raise ConfigError(f"{path}: {line}") from None
        raise ConfigError(format_validation_error(e, str(path))) from None
    if cfg.tool is not None and cfg.cutter is not None:
        raise ConfigError(f"{path}: cutter: give the cutter once: tool: {{type, diameter, "
                          f"corner_radius, ...}} (a run file's tools entry) or the older cutter: "
                          f"{{R, r}}, not both")
    require(mesh_bytes(*cfg.mesh), f"{path}: mesh", f"{cfg.mesh[0]} x {cfg.mesh[1]} cells")
    return cfg


def build_plan(cfg: ZoneBase, base_dir: Path, progress=None):
    """(surface, planner, genes, batch, seconds) of a validated config: the one engine's
    3-axis plan (drop-cutter placement, passes spaced for h_c, each zone along its optimized
    direction) with the method's zones, and the seconds planning took; ValueError for bad
    values. ``progress(name)`` is called as the zoning, then the passes, start."""
    import numpy as np

    from ..problems.toolpath.geometry.spec import parse_surface
    from ..problems.toolpath.plan.planner import Planner
    from ..problems.toolpath.plan.zones import ZoningSpec
    from ..problems.toolpath.plan.zoning.methods import REGISTRY
    from ..problems.toolpath.spec import tool_database

    surface = parse_surface(cfg.surface, "surface", base_dir=base_dir)
    tools = tool_database([cfg.tool_settings()])
    settings = getattr(cfg, cfg.method).model_dump()  # the method's own settings group
    gene = REGISTRY[cfg.method].gene
    genes = {"tool": np.array([0]), "step": np.array([cfg.step])}
    if gene is not None:
        genes[gene.name] = np.array([settings.pop(gene.setting)], float)
    spec = ZoningSpec(cfg.method, settings, tuple(cfg.mesh), cfg.merge, cfg.delta_l, cfg.seed,
                      cfg.stepover_model, cfg.direction_scan, cfg.sample_spacing)
    planner = Planner(surface, tools, machine="3axis", zoning=spec, spacing="scallop",
                      h_c=cfg.h_c, feed_angle=None, strategy=cfg.strategy)
    t0 = time.perf_counter()
    if progress is not None:
        progress(f"zones ({cfg.method}, mesh {cfg.mesh[0]} x {cfg.mesh[1]})")
        layout = planner.layout(genes)  # memoized: the plan below reuses it
        progress(f"passes of {layout.count} zone(s)")
    batch = planner.plan(genes, place=False)
    return surface, planner, genes, batch, time.perf_counter() - t0


def summary(cfg: ZoneBase, planner, genes, batch, seconds: float) -> dict[str, Any]:
    """The plan's figures: every length is the one engine's, of the sections it cuts (zone
    borders crossed by the bands of zoned planes, edge overruns included)."""
    import numpy as np

    layouts = planner.layouts
    layout = planner.layout(genes)  # memoized: the plan's own
    zone_of_seg = batch.sec_zone[batch.seg_sec]
    area = layouts.features.area
    zones = []
    for z in range(layout.count):
        own = batch.sec_zone == z
        zones.append({"zone": z, "cells": int((layout.labels == z).sum()),
                      "area_mm2": round(float(area[layout.labels == z].sum()), 3),
                      "direction_deg": round(float(np.degrees(layout.alpha[z])) % 180, 3),
                      "passes": len(np.unique(batch.sec_pass[own])),
                      "sections": int(own.sum()),
                      "length_mm": round(float(batch.seg_len[zone_of_seg == z].sum()), 3)})
    cutting = float(batch.seg_len.sum())
    penalty = (layout.count - 1) * cfg.delta_l
    chords = np.ones(len(batch.seg_len), bool) if batch.seg_cc is None else batch.seg_cc
    on_part = float(batch.seg_len[chords].sum())
    return {
        "name": cfg.name, "method": layouts.method.name, "mesh": list(cfg.mesh),
        "cutter": planner.tools.cutter(0).to_dict(), "h_c": cfg.h_c,
        "stepover_model": cfg.stepover_model, "step_mm": cfg.step,
        "zones": zones, "n_zones": layout.count,
        "cutting_length_mm": round(cutting, 3),
        "penalty_mm": round(penalty, 3), "delta_l_mm": cfg.delta_l,
        "total_length_mm": round(cutting + penalty, 3),
        "strategy": planner.strategy.name,
        "length_on_part_mm": round(on_part, 3),
        "length_papers_mm": round(on_part + penalty, 3),
        "cc_points": int(batch.on_part.sum()),
        "info": layout.info, "seconds": {"total": round(seconds, 4)},
    }


def toolpath_apt(planner, genes, facts) -> bytes:
    """The plan as an APT CL file (the CL path the machine runs: drop-cutter tips, each
    section one feed motion), so an outside simulator can measure it."""
    import textwrap

    from ..problems.toolpath.export.apt_write import apt_plan

    path = planner.cl_path(genes, float(planner.tools.feeds(1000.0)[0]))
    title = (f"{facts['name']}: {facts['method']} {facts['n_zones']} zones, "
             f"{facts['strategy']}, h_c {facts['h_c']} mm")
    return apt_plan(path, planner.tools.tools[0], part="EVOPLAN ZONE",
                    comments=textwrap.wrap(title, 66)).encode()


def zones_csv(features, labels) -> bytes:
    import numpy as np

    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["i", "j", "u", "v", "zone", "slope_deg", "steepest_deg", "area_mm2"])
    n, m = labels.shape
    for i in range(n):
        for j in range(m):
            w.writerow([i, j, f"{features.u[i, j]:.6f}", f"{features.v[i, j]:.6f}",
                        int(labels[i, j]), f"{np.degrees(features.slope[i, j]):.4f}",
                        f"{np.degrees(features.steepest[i, j]):.4f}",
                        f"{features.area[i, j]:.6f}"])
    return buf.getvalue().encode()


def main(args: argparse.Namespace) -> int:
    from ..problems.toolpath.artifacts import zone_map_png

    cfg = load(args.config, args.method, args.strategy)
    out = Path(args.out or Path("results") / f"{cfg.name}-{time.strftime('%Y%m%d-%H%M%S')}")
    check_out(out)
    from .progress import Stages

    with Stages("zone", 5, getattr(args, "quiet", False)) as stage:
        try:
            surface, planner, genes, batch, seconds = build_plan(cfg, Path(args.config).resolve().parent,
                                                                 progress=stage)
            stage("zones.csv")
            facts = summary(cfg, planner, genes, batch, seconds)
            if surface.facts():
                facts["surface"] = surface.facts()  # a mesh: the fit's measured deviation
            labels = planner.layout(genes).labels
            files = {"summary.json": json.dumps(facts, indent=2).encode(),
                     "zones.csv": zones_csv(planner.layouts.features, labels)}
            stage("zone_map.png")
            files["zone_map.png"] = zone_map_png(surface, batch, labels,
                                                 title=f"{cfg.name}: {facts['method']}, "
                                                       f"{facts['n_zones']} zones, total "
                                                       f"{facts['total_length_mm']:.0f} mm")
            stage(f"toolpath.apt ({int(batch.on_part.sum())} CC points)")
            files["toolpath.apt"] = toolpath_apt(planner, genes, facts)
            stage.finish()
        except ValueError as e:
            raise ConfigError(f"{args.config}: {e}") from None
    write_folder(out, files)  # all files or none (a full disk: one line)
    print(json.dumps({"out": str(out), "method": facts["method"],
                      "zones_from_method": facts["info"].get("merge", {}).get("zones_in"),
                      "zones": facts["n_zones"],
                      "cutting_length_mm": round(facts["cutting_length_mm"], 1),
                      "penalty_mm": facts["penalty_mm"],
                      "total_length_mm": round(facts["total_length_mm"], 1),
                      "strategy": facts["strategy"],
                      "length_on_part_mm": round(facts["length_on_part_mm"], 1),
                      "length_papers_mm": round(facts["length_papers_mm"], 1),
                      "seconds": round(seconds, 3)}))
    return 0
