"""Abbas' roughing comparison: morphing intermediate layers vs z-level, on the three run files.

    python runs/reproduce/abbas_roughing.py [--out PATH | --regenerate]

For each of runs/abbas_gentle.yaml, abbas_narrow_z.yaml and abbas_wide_z.yaml: the same flat
end mill, max depth of cut D_cut, step-over, feeds, allowances and block stock (top =
z_max + 5), roughed once with Abbas' morphing layers and once with the z-level baseline,
both by zig-zag and both simulated on the stock Z-map. Time = cutting / feed + plunge /
plunge feed + rapid / rapid rate; NC size = bytes of the program in the run file's post
dialect (points thinned within the same 0.01 mm tolerance for both). Abbas reports, vs a
contour (z-level) toolpath: -15 % time on case two and equal time on case three; NC size
smaller by a small percentage on cases one and two and by 52 % on case three.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from evoplan.commands.machine import load
from evoplan.problems.toolpath.export.posts import POSTS, Machine
from evoplan.problems.toolpath.roughing.operation_set import _kinematics, _tool
from evoplan.problems.toolpath.roughing.operations import block_stock, roughing
from evoplan.problems.toolpath.geometry.spec import parse_surface
from outputs import add_report_options, resolve_report_paths  # runs/reproduce/outputs.py

RUNS = ["abbas_gentle", "abbas_narrow_z", "abbas_wide_z"]
ABBAS = {"abbas_gentle": ("-", "small reduction"), "abbas_narrow_z": ("-15 %", "small reduction"),
         "abbas_wide_z": ("0 %", "-52 %")}


def compare(name: str) -> dict:
    path = Path(__file__).resolve().parents[1] / f"{name}.yaml"
    cfg = load(str(path)).model_dump()
    surface = parse_surface(cfg["surface"], "surface", path.parent)
    st, al, ro, po = cfg["stock"], cfg["allowances"], cfg["roughing"], cfg["post"]
    stock = block_stock(surface, st["cell"], st["top"], st["top_offset"])
    tool = _tool(ro["tool"])
    cls = POSTS[po["dialect"]]
    post = cls(Machine(_kinematics(po["kinematics"]) if cls.five_axis else None))
    out = {"z_range": stock.z_max - stock.z_min}
    for method in ("morphing", "zlevel"):
        t0 = time.perf_counter()
        # Abbas' layers as he draws them, each over the whole block (abbas_fair_baseline.py
        # also measures them cut only where material remains)
        tp, stats, _ = roughing(stock, "morphing_full" if method == "morphing" else method, tool, d_cut=ro["max_depth"], stepover=ro["stepover"] * tool.diameter,
                                allowance_semi=al["semifinish"], allowance_finish=al["finish"], feed=ro["feed"],
                                plunge_feed=ro["plunge_feed"], tolerance=ro["tolerance"])
        nc = post.program(tp, "roughing").encode()
        out[method] = {"time": tp.time_minutes(po["rapid_rate"]), "nc": len(nc), "layers": stats["n_layers"],
                       "depth": stats["max_depth"], "air": stats["air_length"], "removed": stats["removed_mm3"],
                       "left_max": stats["left_max"], "left_min": stats["left_min"], "lengths": tp.lengths(),
                       "seconds": time.perf_counter() - t0}
    return out


def table(results: dict) -> str:
    rows = ["| case | z range (mm) | layers | time morph / z-level (min) | time change | Abbas time | "
            "NC morph / z-level (kB) | NC change | Abbas NC | max depth morph / z-level (mm) | "
            "air cut morph / z-level (mm) | removed morph / z-level (cm3) | left above surface max, "
            "morph / z-level (mm) |",
            "|" + "---|" * 13]
    for name, r in results.items():
        m, z = r["morphing"], r["zlevel"]
        rows.append(
            f"| {name} | {r['z_range']:.1f} | {m['layers']} | {m['time']:.2f} / {z['time']:.2f} | "
            f"{100 * (m['time'] / z['time'] - 1):+.0f} % | {ABBAS[name][0]} | {m['nc'] / 1e3:.1f} / {z['nc'] / 1e3:.1f} | "
            f"{100 * (m['nc'] / z['nc'] - 1):+.0f} % | {ABBAS[name][1]} | {m['depth']:.2f} / {z['depth']:.2f} | "
            f"{m['air']:.0f} / {z['air']:.0f} | {m['removed'] / 1e3:.1f} / {z['removed'] / 1e3:.1f} | "
            f"{m['left_max']:.2f} / {z['left_max']:.2f} |")
    return "\n".join(rows) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_report_options(parser)
    args = parser.parse_args()
    resolve_report_paths(args, __file__)
    results = {name: compare(name) for name in RUNS}
    text = table(results)
    print(text)
    for name, r in results.items():
        for method in ("morphing", "zlevel"):
            ln = r[method]["lengths"]
            print(f"{name} {method}: cutting {ln['cutting']:.0f} mm, plunge {ln['plunge']:.0f} mm, "
                  f"rapid {ln['rapid']:.0f} mm, min left {r[method]['left_min']:.3f} mm, "
                  f"{r[method]['seconds']:.2f} s")
    head = Path(args.out).read_text().split("<!-- table -->")[0] if Path(args.out).exists() else "# Abbas roughing\n\n"
    Path(args.out).write_text(head + "<!-- table -->\n" + text)


if __name__ == "__main__":
    main()
