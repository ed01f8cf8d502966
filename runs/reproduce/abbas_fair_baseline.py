"""Abbas' roughing comparison on a fair baseline: morphing layers vs contour-parallel z-level.

For the three shipped surfaces (runs/abbas_gentle.yaml, abbas_narrow_z.yaml, abbas_wide_z.yaml)
at each file's depth of cut and step-over (the same for every method), the roughing of each
method (morphing, contour, zlevel zig-zag): kinematic time (jerk 40 m/s^3, acceleration 6
m/s^2, rapids 10 m/min, each file's feeds), nominal time (length / feed), ISO NC size (points
already thinned within the file's tolerance), and the stock left (Z-map). Prints a table and
morphing vs contour in %. Abbas reports -15 % time on case two and -52 % NC size on case three.

    python runs/reproduce/abbas_fair_baseline.py [--out DIR]   (default /tmp/abbas_fair_baseline)
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from evoplan.commands.machine import load
from evoplan.problems.toolpath.criteria.kinematic_time import Dynamics, toolpath_time
from evoplan.problems.toolpath.export.posts import POSTS, Machine
from evoplan.problems.toolpath.export.toolpath import Tool
from evoplan.problems.toolpath.geometry.spec import parse_surface
from evoplan.problems.toolpath.roughing.operations import block_stock, roughing

RUNS = Path(__file__).resolve().parent.parent
CASES = ("abbas_gentle", "abbas_narrow_z", "abbas_wide_z")
METHODS = ("morphing", "contour", "zlevel")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="/tmp/abbas_fair_baseline")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    print(f"{'case':16s} {'method':9s} {'kin min':>8s} {'L/F min':>8s} {'NC bytes':>9s} {'left min':>8s} "
          f"{'left max':>8s} {'max depth':>9s}")
    for case in CASES:
        cfg = load(str(RUNS / f"{case}.yaml")).model_dump()
        surface = parse_surface(cfg["surface"], "surface", RUNS)
        st, al, ro = cfg["stock"], cfg["allowances"], cfg["roughing"]
        stock = block_stock(surface, st["cell"], st["top"], st["top_offset"])
        tool = Tool(ro["tool"]["number"], ro["tool"]["diameter"], 0.0, ro["tool"]["spindle"])
        for method in METHODS:
            tp, stats, _ = roughing(stock, method, tool, d_cut=ro["max_depth"], stepover=ro["stepover"] * tool.diameter,
                                    allowance_semi=al["semifinish"], allowance_finish=al["finish"], feed=ro["feed"],
                                    plunge_feed=ro["plunge_feed"], tolerance=ro["tolerance"])
            nc = POSTS["iso"](Machine()).program(tp, "rough").encode()
            (out / f"{case}_{method}.nc").write_bytes(nc)
            row = {"case": case, "method": method, "kinematic_min": toolpath_time(tp, Dynamics(rapid=10000.0)),
                   "nominal_min": tp.time_minutes(10000.0), "nc_bytes": len(nc), "left_min": stats["left_min"],
                   "left_max": stats["left_max"], "max_depth": stats["max_depth"]}
            rows.append(row)
            print(f"{case:16s} {method:9s} {row['kinematic_min']:8.2f} {row['nominal_min']:8.2f} {len(nc):9d} "
                  f"{row['left_min']:8.3f} {row['left_max']:8.3f} {row['max_depth']:9.3f}")
    print("\nmorphing vs contour baseline:")
    for case in CASES:
        m, c = (next(r for r in rows if r["case"] == case and r["method"] == k) for k in ("morphing", "contour"))
        print(f"  {case:16s} time {100 * (m['kinematic_min'] / c['kinematic_min'] - 1):+6.1f} %   "
              f"NC size {100 * (m['nc_bytes'] / c['nc_bytes'] - 1):+6.1f} %")
    (out / "abbas_fair_baseline.json").write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
