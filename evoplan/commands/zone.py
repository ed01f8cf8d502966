"""``evoplan zone CONFIG [--out DIR]``: zone a surface, optimize each zone's feed direction.

The file names the surface, the cutter (R, r), the scallop limit h_c, the zone-change
penalty Delta L, the parametric mesh, the zoning method (any name of the registry in
``problems/toolpath/plan/zoning/methods/``: single, kmeans, amas) with a settings group per method,
and ``merge`` (the post-process of ``zoning/merge.py``); see ``runs/choi_zoning.yaml``. The
config model is built from the registry, so this command holds no method logic. Writes
``summary.json`` (method, zones, per-zone direction and length, total length of Djebali
Eq. 4, penalty, merge counts, seconds), ``zones.csv``
(cell -> zone, with the cell's features) and ``zone_map.png`` (the zones and their passes).
Nothing is written unless the whole plan succeeds.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import time
from pathlib import Path
from typing import Any, Literal

from pydantic import Field, ValidationError, create_model, field_validator

from ..config import SafeName, _Strict, format_validation_error, read_yaml
from ..engine import write_atomic
from ..errors import ConfigError, EvoplanError
from ..limits import mesh_bytes, require
from ..problems.toolpath.plan.zoning.merge import MergeSettings
from ..problems.toolpath.plan.zoning.methods import REGISTRY


class CutterConfig(_Strict):
    R: float = 3.175
    r: float = 1.0


class ZoneBase(_Strict):
    name: SafeName = "zoning"
    surface: Any = "choi"
    cutter: CutterConfig = Field(default_factory=CutterConfig)
    h_c: float = 0.254
    delta_l: float = 40.0
    mesh: list[int] = Field(default_factory=lambda: [70, 70], min_length=2, max_length=2)
    method: str = Field("amas", description="a registered zoning method: single, kmeans, amas")
    seed: int = 0
    merge: MergeSettings = Field(default_factory=MergeSettings)
    stepover_model: Literal["profile", "circle"] = "profile"
    sample_spacing: float = Field(0.25, gt=0)
    direction_scan: int = Field(12, ge=1)

    @field_validator("method")
    @classmethod
    def _registered(cls, v: str) -> str:
        if v not in REGISTRY:
            raise ValueError(f"expected one of {', '.join(REGISTRY)}")
        return v


def zone_config_model() -> type[ZoneBase]:
    """The zoning-file model: ``ZoneBase`` plus one settings group per registered method."""
    groups = {name: (m.Settings, Field(default_factory=m.Settings, description=m.description))
              for name, m in REGISTRY.items()}
    return create_model("ZoneConfig", __base__=ZoneBase, **groups)


ZoneConfig = zone_config_model()  # the built-in methods' model (docs/zoning.md lists its keys)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("zone", help="zone a surface and optimize each zone's feed direction")
    p.add_argument("config", help="YAML zoning file (e.g. runs/choi_zoning.yaml)")
    p.add_argument("--out", help="results folder (default: results/<name>-<time>)")
    p.add_argument("--method", metavar="NAME",
                   help=f"override the method (registered: {', '.join(REGISTRY)})")
    return p


def load(path: str, method: str | None = None) -> ZoneBase:
    """The validated zoning file (``method``: the --method override); ConfigError."""
    data = read_yaml(path)
    data.setdefault("name", Path(path).stem)
    if method is not None:
        data["method"] = method
    try:
        cfg = zone_config_model().model_validate(data)
    except ValidationError as e:
        raise ConfigError(format_validation_error(e, str(path))) from None
    require(mesh_bytes(*cfg.mesh), f"{path}: mesh", f"{cfg.mesh[0]} x {cfg.mesh[1]} cells")
    return cfg


def build_plan(cfg: ZoneBase, base_dir: Path):
    """(surface, samples, plan) of a validated config; ValueError for bad values."""
    from ..problems.toolpath.geometry.spec import parse_surface
    from ..problems.toolpath.plan.zoning.plan import plan_zones
    from ..problems.toolpath.plan.zoning.samples import sample_surface
    from ..problems.toolpath.plan.zoning.stepover import ScallopTarget

    surface = parse_surface(cfg.surface, "surface", base_dir=base_dir)
    target = ScallopTarget.build(cfg.cutter.R, cfg.cutter.r, cfg.h_c, key="cutter")
    samples = sample_surface(surface, spacing=cfg.sample_spacing)
    settings = getattr(cfg, cfg.method).model_dump()  # the method's own settings group
    plan = plan_zones(surface, target, cfg.method, mesh=tuple(cfg.mesh), delta_l=cfg.delta_l,
                      model=cfg.stepover_model, samples=samples, scan=cfg.direction_scan,
                      seed=cfg.seed, merge=cfg.merge, **settings)
    return surface, samples, plan


def summary(cfg: ZoneBase, plan) -> dict[str, Any]:
    return {
        "name": cfg.name, "method": plan.method, "mesh": list(cfg.mesh),
        "cutter": {"R": cfg.cutter.R, "r": cfg.cutter.r}, "h_c": cfg.h_c,
        "stepover_model": cfg.stepover_model,
        "zones": [{"zone": z.zone, "cells": z.cells, "area_mm2": round(z.area, 3),
                   "start_direction_deg": round(z.start_deg % 180, 3),
                   "direction_deg": round(z.direction_deg % 180, 3),
                   "start_length_mm": round(z.start_length, 3),
                   "length_mm": round(z.length, 3), "passes": len(z.passes.s),
                   "lower_bound_mm": round(z.lower_bound, 3), "evaluations": z.evaluations}
                  for z in plan.zones],
        "n_zones": len(plan.zones),
        "cutting_length_mm": round(plan.cutting_length, 3),
        "penalty_mm": round(plan.penalty, 3), "delta_l_mm": plan.delta_l,
        "total_length_mm": round(plan.total_length, 3),
        "link_length_mm": round(plan.link_length, 3),
        "info": plan.info, "seconds": {k: round(v, 4) for k, v in plan.seconds.items()},
    }


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
    from ..problems.toolpath.plan.zoning.figures import zone_map_png

    cfg = load(args.config, args.method)
    out = Path(args.out or Path("results") / f"{cfg.name}-{time.strftime('%Y%m%d-%H%M%S')}")
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise EvoplanError(f"{out}: already exists and is not empty: choose another --out")
    try:
        surface, samples, plan = build_plan(cfg, Path(args.config).resolve().parent)
        files = {"summary.json": json.dumps(summary(cfg, plan), indent=2).encode(),
                 "zones.csv": zones_csv(plan.features, plan.labels),
                 "zone_map.png": zone_map_png(surface, plan, samples,
                                              title=f"{cfg.name}: {plan.method}, "
                                                    f"{len(plan.zones)} zones, total "
                                                    f"{plan.total_length:.0f} mm")}
    except ValueError as e:
        raise ConfigError(f"{args.config}: {e}") from None
    out.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        write_atomic(out / name, data)
    print(json.dumps({"out": str(out), "method": plan.method,
                      "zones_from_method": plan.info.get("merge", {}).get("zones_in"),
                      "zones": len(plan.zones),
                      "cutting_length_mm": round(plan.cutting_length, 1),
                      "penalty_mm": plan.penalty,
                      "total_length_mm": round(plan.total_length, 1),
                      "seconds": round(plan.seconds["total"], 3)}))
    return 0
