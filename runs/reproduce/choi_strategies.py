"""Choi's surface: every finishing strategy, single zone and zoned, judged on three grids.

    python runs/reproduce/choi_strategies.py [--quick] [--out PATH | --regenerate]

Choi's surface (Djebali Table 3), h_c = 0.254 mm, R = 3.175 mm, 3-axis drop-cutter
placement, CC points at most 1 mm apart, chord tolerance 0.01 mm. Plans: the ball single
zone and the torus r 1 single zone and zoned (K-means K = 2..6, AMAS k_LZ 0.15), each with
every strategy of ``plan/strategies``. Per plan: zones, on-part length (the feed moves
between CC points on the part, as the papers count), papers' length (+ 40 mm a zone, Eq. 4
on the part), Eq. 4 total (with the runs past the edge), CC count, the simulated max / p99
on 0.2, 0.1 and 0.05 mm grids and the verdict (``simulation.metrics.meets_h_c``: p99 < h_c,
max <= 1.1 h_c, nothing uncut, gouge <= tolerance) on each; a verdict that changes between
0.1 and 0.05 mm is flagged. ``--quick``: the single zones and K-means K = 3 only.
Writes the report to ``--out`` (default ``results/reproduce/choi_strategies.md`` under the
current directory); ``--regenerate`` rewrites the committed copy beside this script.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from evoplan.problems.toolpath.criteria.analytic import analytic_criteria
from evoplan.problems.toolpath.geometry.spec import parse_surface
from evoplan.problems.toolpath.plan.planner import Planner
from evoplan.problems.toolpath.plan.strategies import STRATEGIES
from evoplan.problems.toolpath.plan.zones import ZoningSpec
from evoplan.problems.toolpath.simulation import design_grid, simulate
from evoplan.problems.toolpath.simulation.metrics import VERDICT_GRIDS_MM, verdicts
from evoplan.problems.toolpath.spec import parse_tools
from evoplan.problems.toolpath.tools import CHOI_TOOLS
from outputs import add_report_options, resolve_report_paths, write_report  # runs/reproduce/outputs.py

H_C, DELTA_L, STEP, TOL, ALLOWANCE = 0.254, 40.0, 1.0, 0.01, 0.5
PUBLISHED = "1717 mm (Choi, ball, iso-scallop), 1183 mm (Djebali, AMAS, torus r 1), " \
            "1437 mm (Herraz, K-means, torus r 1.27)"


def cases(quick: bool):
    out = [("single", 0, None), ("single", 1, None)]
    out += [("kmeans", 1, k) for k in ((3,) if quick else (2, 3, 4, 5, 6))]
    if not quick:
        out.append(("amas", 1, 0.15))
    return out


def run(args) -> str:
    surface, tools = parse_surface("choi"), parse_tools(CHOI_TOOLS)
    grids = {h: design_grid(surface, h) for h in VERDICT_GRIDS_MM}
    rows = []
    for method, tool, value in cases(args.quick):
        zoning = None if method == "single" else ZoningSpec(method)
        for name in STRATEGIES:
            pl = Planner(surface, tools, machine="3axis", zoning=zoning, spacing="scallop",
                         h_c=H_C, feed_angle=None, strategy=name, tolerance=TOL)
            genes = {"tool": np.array([tool]), "step": np.array([STEP])}
            if pl.layouts.gene is not None:
                genes[pl.layouts.gene] = np.array([value])
            t0 = time.perf_counter()
            batch = pl.plan(genes, place=False)
            crit = analytic_criteria(batch, surface, tools, genes, allowance=ALLOWANCE,
                                     feed_rate=1000.0, delta_l=DELTA_L, machine="3axis")
            path = pl.cl_path(genes)
            seconds = time.perf_counter() - t0
            sims = {h: simulate(path, g, allowance=ALLOWANCE).metrics for h, g in grids.items()}
            v = verdicts(sims, H_C, TOL)
            rows.append((method, tools.tools[tool], value, name, crit, sims, v, seconds))
            print(f"{method} {value} tool {tool} {name}: papers "
                  f"{crit['length_papers_mm'][0]:.1f} mm, 0.05 max "
                  f"{sims[0.05]['scallop_max_mm']:.3f} p99 {sims[0.05]['scallop_p99_mm']:.3f} "
                  f"meets {v['final']}{' FLIP' if v['flip'] else ''}", flush=True)
    return table(rows, args.quick)


def table(rows, quick) -> str:
    head = ("| zoning | tool | strategy | zones | on part | papers | Eq. 4 total | CC | "
            + " | ".join(f"max / p99 @{h}" for h in VERDICT_GRIDS_MM)
            + " | meets h_c @" + " / ".join(str(h) for h in VERDICT_GRIDS_MM) + " |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for method, tool, value, name, crit, sims, v, _ in rows:
        zoning = method if value is None else f"{method} {value:g}"
        t = "ball" if tool.corner_radius >= tool.diameter / 2 else f"torus r {tool.corner_radius:g}"
        sim = " | ".join(f"{sims[h]['scallop_max_mm']:.3f} / {sims[h]['scallop_p99_mm']:.3f}"
                         for h in VERDICT_GRIDS_MM)
        ok = " / ".join("yes" if v["by_grid"][h][0] else "no" for h in VERDICT_GRIDS_MM)
        lines.append(f"| {zoning} | {t} | {name} | {int(crit['zones'][0])} | "
                     f"{crit['length_on_part_mm'][0]:.1f} | {crit['length_papers_mm'][0]:.1f} | "
                     f"{crit['eq4_total'][0]:.1f} | {int(crit['cc_count'][0])} | {sim} | {ok}"
                     f"{' **FLIP**' if v['flip'] else ''} |")
    return ("# Choi's surface: finishing strategies judged on three grids\n\n"
            f"Generated by `runs/reproduce/choi_strategies.py{' --quick' if quick else ''}`. "
            f"h_c {H_C} mm, R 3.175 mm, step {STEP} mm, tolerance {TOL} mm. Lengths in mm: "
            "*on part* the feed moves between CC points on the part, *papers* that + 40 mm "
            "a zone, *Eq. 4 total* with the runs past the edge. Published: "
            f"{PUBLISHED}.\n\n" + "\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    add_report_options(ap)
    args = ap.parse_args()
    resolve_report_paths(args, __file__)
    text = run(args)
    write_report(args, text)


if __name__ == "__main__":
    main()
