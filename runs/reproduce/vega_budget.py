"""Where VEGA's and the GA's evaluations go on Kubota's function, and whether the VrsLgth cap binds.

Part 1, at Fountas' best settings (``runs/kubota_vega.yaml``: population 20, 50 generations,
7 viruses, VrsLgth 40, infectivity force 0.001, infection rate 70 %) and for the GA of
``runs/kubota_ga.yaml``, over N seeds: genotypes asked for, infections made, infections that
left their host unchanged (no longer evaluated), cache hits (genotypes seen before in the run),
and the black-box evaluations actually made.

Part 2: for each cap ``virus.max_length`` (10, 20, 30, 40) and life rule (fountas, kubota),
the longest virus there has been in each run (median and maximum over seeds) and the median
age of the living viruses over all generations. A VrsLgth study varies the cap only if the
longest virus reaches it.

    python runs/reproduce/vega_budget.py [--seeds 30]      # writes runs/reproduce/vega_budget.md
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from evoplan.config import load_config
from evoplan.engine import run
from evoplan.runner import prepare
from outputs import add_report_options, resolve_report_paths, write_report  # runs/reproduce/outputs.py

RUNS = Path(__file__).resolve().parents[1]


def one(config, seed: int, virus: dict | None = None) -> dict:
    if virus:
        algo = config.algorithm.model_copy(update={"virus": config.algorithm.virus.model_copy(update=virus)})
        config = config.model_copy(update={"algorithm": algo})
    p = prepare(config.model_copy(update={"seed": seed}))
    ages: list[np.ndarray] = []
    state = run(p.new_state(), p.space, p.evaluator, p.termination,
                on_generation=lambda s: ages.append(s.algorithm.age.copy()) if hasattr(s.algorithm, "age") else None)
    a = state.algorithm
    return {"asked": state.evaluations + state.cache_hits + getattr(a, "infections_unchanged", 0),
            "infections": getattr(a, "infections_made", 0), "unchanged": getattr(a, "infections_unchanged", 0),
            "hits": state.cache_hits, "evaluated": state.cache.misses, "best": state.best_f,
            "longest": getattr(a, "longest", 0), "ages": np.concatenate(ages) if ages else np.zeros(0)}


def saving(seeds: range) -> list[str]:
    lines = ["## Where the evaluations go (Kubota, 50 generations, population 20)", "",
             "| algorithm | asked | infections | unchanged infections | cache hits | evaluated | saved |",
             "|---|---|---|---|---|---|---|"]
    for name in ("kubota_vega", "kubota_ga"):
        cfg = load_config(RUNS / f"{name}.yaml")
        rows = [one(cfg, s) for s in seeds]
        tot = {k: sum(r[k] for r in rows) for k in ("asked", "infections", "unchanged", "hits", "evaluated")}
        inf = f"{tot['infections']}" if tot["infections"] else "-"
        unch = f"{tot['unchanged']} ({100 * tot['unchanged'] / tot['infections']:.1f} %)" if tot["infections"] else "-"
        lines.append(f"| {name} | {tot['asked']} | {inf} | {unch} | {tot['hits']} "
                     f"({100 * tot['hits'] / tot['asked']:.1f} %) | {tot['evaluated']} | "
                     f"{100 * (1 - tot['evaluated'] / tot['asked']):.1f} % |")
    lines += ["", f"Totals over {len(seeds)} seeds. *asked*: every genotype the algorithm produced; "
              "*unchanged infections* are no longer asked for; *cache hits* are asked but answered by the "
              "cache; *evaluated* = calls of the objective.", ""]
    return lines


def cap_check(seeds: range) -> list[str]:
    cfg = load_config(RUNS / "kubota_vega.yaml")
    lines = ["## Does the VrsLgth cap bind? (Kubota, Fountas' best settings but the cap)", "",
             "| life_rule | cap | longest virus (median over seeds) | longest (max) | runs at the cap "
             "| median virus age (generations) |", "|---|---|---|---|---|---|"]
    for rule in ("fountas", "kubota"):
        for cap in (10, 20, 30, 40):
            rows = [one(cfg, s, {"max_length": cap, "life_rule": rule}) for s in seeds]
            longest = np.array([r["longest"] for r in rows])
            age = np.median(np.concatenate([r["ages"] for r in rows]))
            lines.append(f"| {rule} | {cap} | {np.median(longest):.0f} | {longest.max()} | "
                         f"{int((longest >= cap).sum())}/{len(rows)} | {age:.0f} |")
    lines += ["", "Fresh viruses are at most cap // 4 long (`initial_length` unset); growth 1 locus per "
              "partial transduction.", ""]
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=30)
    add_report_options(ap)
    args = ap.parse_args()
    resolve_report_paths(args, __file__)
    seeds = range(1, args.seeds + 1)
    text = "\n".join(["# VEGA's evaluation budget on Kubota's function", "",
                      f"`python runs/reproduce/vega_budget.py --seeds {args.seeds}`", ""]
                     + saving(seeds) + cap_check(seeds))
    write_report(args, text)


if __name__ == "__main__":
    main()
