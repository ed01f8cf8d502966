"""Fountas Table 2 analog: the two published parameter sets evaluated by evoplan's simulator.

    python runs/reproduce/fountas_table2.py [--config runs/fountas_toolpath_vega.yaml] [--out runs/reproduce/fountas_table2.md]

Writes a Markdown table (CC count, mean and max chord error, max scallop, machining error,
path length, time at the configured feed rate) beside the paper's figures.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from evoplan.runner import prepare_file

HERE = Path(__file__).resolve().parent
PUBLISHED = {  # Fountas Table 2 and "Algorithmic validation"
    "GA": {"params": {"tool": 6, "stepover": 30.791, "lead": 3.379, "tilt": 0.040, "step": 8.451},
           "cc_count": 337, "chord_error_mean": 0.0043, "objective": 0.361086},
    "VEGA": {"params": {"tool": 6, "stepover": 41.729, "lead": 2.957, "tilt": 0.027, "step": 6.338},
             "cc_count": 289, "chord_error_mean": 0.0036, "objective": 0.359608},
}
ROWS = [  # criterion, label, format
    ("cc_count", "CC points", "{:.0f}"),
    ("n_passes", "passes", "{:.0f}"),
    ("chord_error_mean", "mean chord error (mm)", "{:.4f}"),
    ("chord_error_max", "max chord error (mm)", "{:.4f}"),
    ("scallop_max", "max scallop (mm)", "{:.3f}"),
    ("gouge_max", "max gouge (mm)", "{:.3f}"),
    ("machining_error", "max machining error (mm)", "{:.3f}"),
    ("r_eff", "effective radius (mm)", "{:.1f}"),
    ("path_length", "path length (mm)", "{:.0f}"),
    ("machining_time", "time (min)", "{:.2f}"),
    ("objective", "objective (Eq. 9)", "{:.4f}"),
]


WHY = """\
- CC points: passes are planes spaced in XY at step-over x D across the 103.2 mm of the part
  ({ga_passes:.0f} planes for GA, {vega_passes:.0f} for VEGA), each sampled at the maximum
  step along the 96.5 mm pass, then refined where the chord error exceeds 0.01 mm
  ({ga_pts:.1f} and {vega_pts:.1f} points per pass). The VEGA set reproduces the paper's 289
  exactly (17 x 17, no segment over the tolerance). For the GA set 8.0 mm segments exceed the
  tolerance on the curved part and each is split; CATIA's rule for where to add points is not
  published (it gave 337, 51 more than the unrefined 286).
- Mean chord error: evoplan measures the true distance from the pass curve to each chord;
  with the VEGA set's identical point spacing the paper's 0.0036 mm would need segments about
  17 % shorter, so CATIA measures it differently (the GA/VEGA ratio, 1.13 here, is close to
  the paper's 1.19).
- Scallop and machining error: tool 6 is the toroidal D16 r3; at a lead of about 3 deg its
  effective radius is {ga_reff:.0f} mm (GA) and {vega_reff:.0f} mm (VEGA), a nearly flat profile,
  so on this part (concave across the feed everywhere, slopes up to 53.5 deg that stretch
  the XY spacing on the surface) the simulated cusps and gouges exceed the paper's +-0.0103 mm
  tolerance analysis, which came from CATIA's own gouge-free toolpath.
- Objective: Eq. 9 values depend on the normalization bounds, which the paper does not give;
  evoplan fixes them from a design of 217 parameter sets at construction, so only the
  ranking is comparable, and here it is reversed: the simulator prefers the GA set
  (denser passes, smaller cusps).
- Time: the paper's times came from the CNC (approach, rapids, acceleration); evoplan's is
  path length / feed rate.
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--config", default=str(HERE.parent / "fountas_toolpath_vega.yaml"))
    ap.add_argument("--out", default=str(HERE / "fountas_table2.md"))
    args = ap.parse_args()
    problem = prepare_file(args.config).evaluator.problem
    feed = problem.simulator.feed_rate
    results = {k: problem.evaluate_params(v["params"]) for k, v in PUBLISHED.items()}
    lines = [
        "# Fountas Table 2 analog",
        "",
        f"The two published parameter sets evaluated by evoplan's simulator ({Path(args.config).name}, feed "
        f"{feed:g} mm/min). Tool 6 is the toroidal D16 r3 of the default database.",
        "",
        "| criterion | GA (simulated) | VEGA (simulated) | GA (paper) | VEGA (paper) |",
        "|---|---|---|---|---|",
    ]
    for key, label, fmt in ROWS:
        paper = [PUBLISHED[a].get(key) for a in ("GA", "VEGA")]
        cells = [fmt.format(results[a][key]) for a in ("GA", "VEGA")]
        cells += ["" if p is None else f"{p:g}" for p in paper]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    for a, v in PUBLISHED.items():
        p = v["params"]
        lines.append("")
        lines.append(f"{a}: tool {p['tool']}, step-over {p['stepover']} %, lead {p['lead']} deg, "
                     f"tilt {p['tilt']} deg, step {p['step']} mm.")
    ga, vega = results["GA"], results["VEGA"]
    lines += ["", "## Why the numbers differ", "", WHY.format(
        ga_passes=ga["n_passes"], ga_pts=ga["cc_count"] / ga["n_passes"],
        vega_passes=vega["n_passes"], vega_pts=vega["cc_count"] / vega["n_passes"],
        ga_reff=ga["r_eff"], vega_reff=vega["r_eff"])]
    text = "\n".join(lines) + "\n"
    Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
