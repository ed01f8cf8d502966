"""Kubota's function over many seeds: the shipped GA and VEGA run files, side by side.

Runs ``runs/kubota_ga.yaml`` and ``runs/kubota_vega.yaml`` (population 20, 50 generations, 46
bits) for seeds 1..N, plus the GA given VEGA's mean number of evaluations (equal budget), and
prints the median, quartiles and best of the final best value and the mean evaluations used,
beside the published figures (Fountas' VEGA 5.55e-17, Kubota's VEGA 8.12e-5, SSGA 1.00e-4).

    python runs/bench/kubota_seeds.py [--seeds 30] [--csv results/kubota_seeds.csv]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from evoplan.config import load_config
from evoplan.engine import run
from evoplan.problems.benchmarks import Kubota
from evoplan.runner import prepare

RUNS = Path(__file__).resolve().parents[1]
PUBLISHED = {"Fountas VEGA (best)": 5.55e-17, "Kubota VEGA": 8.12e-5, "Kubota SSGA": 1.00e-4}


def one(config, seed: int) -> dict:
    p = prepare(config.model_copy(update={"seed": seed}))
    state = run(p.new_state(), p.space, p.evaluator, p.termination)
    return {"best": state.best_f, "evaluations": state.evaluations, "generations": state.algorithm.generation}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=30)
    ap.add_argument("--csv", help="also write every run's result to this CSV file")
    args = ap.parse_args()
    seeds = range(1, args.seeds + 1)
    ga, vega = load_config(RUNS / "kubota_ga.yaml"), load_config(RUNS / "kubota_vega.yaml")
    rows = [{"label": "GA, 50 generations", "seed": s, **one(ga, s)} for s in seeds]
    rows += [{"label": "VEGA, 50 generations", "seed": s, **one(vega, s)} for s in seeds]
    budget = int(np.mean([r["evaluations"] for r in rows if r["label"].startswith("VEGA")]))
    ga_budget = ga.model_copy(update={"termination": ga.termination.model_copy(
        update={"generations": None, "evaluations": budget})})
    rows += [{"label": f"GA, {budget} evaluations", "seed": s, **one(ga_budget, s)} for s in seeds]
    df = pd.DataFrame(rows)
    if args.csv:
        Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
        df.to_csv(args.csv, index=False)
    # Eq. 8 with 23 bits on [-1, 1] cannot code 0: the nearest codes are +-1/(2^23 - 1)
    h = 1.0 / (2**23 - 1)
    codec_floor = float(Kubota().evaluate(np.array([[h, h]]))[0, 0])
    print(f"Kubota (Eq. 13), population 20, 46 bits, {args.seeds} seeds")
    print(f"{'':28s} {'median':>10s} {'q25':>10s} {'q75':>10s} {'best':>10s} {'mean evals':>10s} {'at floor':>8s}")
    for label, g in df.groupby("label", sort=False):
        b = g["best"].to_numpy()
        q25, med, q75 = np.percentile(b, [25, 50, 75])
        at_floor = int((b <= codec_floor * (1 + 1e-9)).sum())
        print(f"{label:28s} {med:10.3g} {q25:10.3g} {q75:10.3g} {b.min():10.3g} {g['evaluations'].mean():10.0f} "
              f"{at_floor:5d}/{len(b)}")
    print(f"lowest value the 23-bit codec can reach (|x| = |y| = {h:.3g}): {codec_floor:.3g}")
    for name, value in PUBLISHED.items():
        print(f"published {name:22s} {value:.3g}")


if __name__ == "__main__":
    main()
