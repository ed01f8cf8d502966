"""Kinematic machining time vs length / feed: does the ranking of plans change?

Two sets of plans, each judged by ``machining_time`` (jerk-limited S-curve, the default
dynamics: jerk 40 m/s^3, acceleration 6 m/s^2, feed 5 m/min) and by the length at the same
feed (path length / 5000 mm/min):

1. Choi's surface zoned (``runs/choi_zoning.yaml``) by every zoning method and pass strategy;
2. Fountas' Table 2 GA and VEGA sets plus a seeded design of 40 decision sets on Eq. 14.

Prints one table per set and Kendall's tau between the two rankings.
    python runs/reproduce/kinematic_time_ranking.py [--design N]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from scipy.stats import kendalltau

from evoplan.commands.zone import build_plan, load
from evoplan.problems.toolpath import ToolpathProblem
from evoplan.problems.toolpath.criteria.kinematic_time import Dynamics, plan_times

RUNS = Path(__file__).resolve().parent.parent
FEED = 5000.0
PUBLISHED = {"GA": {"tool": 6, "stepover": 30.791, "lead": 3.379, "tilt": 0.040, "step": 8.451},
             "VEGA": {"tool": 6, "stepover": 41.729, "lead": 2.957, "tilt": 0.027, "step": 6.338}}


def table(rows):
    print(f"{'plan':34s} {'length mm':>10s} {'L/F min':>8s} {'kin min':>8s} {'ratio':>6s} "
          f"{'rank L':>6s} {'rank kin':>8s}")
    nom = np.array([r[2] for r in rows])
    kin = np.array([r[3] for r in rows])
    rn, rk = nom.argsort().argsort() + 1, kin.argsort().argsort() + 1
    for (name, length, n, k), a, b in zip(rows, rn, rk):
        print(f"{name:34s} {length:10.0f} {n:8.3f} {k:8.3f} {k / n:6.2f} {a:6d} {b:8d}")
    tau = kendalltau(nom, kin).statistic
    print(f"Kendall tau (length ranking vs kinematic ranking): {tau:.3f}; "
          f"same order: {bool((rn == rk).all())}\n")


def choi_rows():
    rows = []
    for method in ("single", "kmeans", "amas"):
        for strategy in ("parallel", "isoscallop", "isoparametric"):
            try:
                cfg = load(str(RUNS / "choi_zoning.yaml"), method=method, strategy=strategy)
                _, planner, genes, batch, _ = build_plan(cfg, RUNS)
            except (ValueError, SystemExit) as e:
                print(f"  {method}/{strategy}: skipped ({str(e).splitlines()[0]})")
                continue
            seg = np.linalg.norm(np.diff(batch.p, axis=0), axis=1)
            length = float(seg.sum())  # the whole chain (cutting, links, inter-zone moves)
            kin = float(plan_times(batch, Dynamics(feed=FEED), FEED)[0])
            rows.append((f"choi {method} {strategy} ({int(batch.zones[0])} zones)", length, length / FEED, kin))
    return rows


def fountas_rows(n_design):
    kw = dict(weights={"cc_count": 1.0}, normalization={"cc_count": [0, 1]}, feed_rate=FEED,
              dynamics={"feed": FEED})
    p = ToolpathProblem(**kw)
    X = np.vstack([p.row(v) for v in PUBLISHED.values()] + [p.genes.design(n_design, 11)])
    c = p.criteria(X)
    names = list(PUBLISHED) + [f"design {i}" for i in range(n_design)]
    return [(n, float(c["path_length"][i]), float(c["machining_time_nominal"][i]), float(c["machining_time"][i]))
            for i, n in enumerate(names)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--design", type=int, default=40)
    args = ap.parse_args()
    print("Choi's surface, zoned (runs/choi_zoning.yaml), 3-axis toroidal, h_c 0.254 mm")
    table(choi_rows())
    print("Fountas Eq. 14, Table 2 sets + a seeded design (5-axis)")
    table(fountas_rows(args.design))


if __name__ == "__main__":
    main()
