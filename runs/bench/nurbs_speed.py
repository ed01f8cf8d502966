"""Benchmark: toolpath evaluations on a NURBS face against the same face as a B-spline.

Two problems in one process: the surface given as ``type: nurbs`` with every weight 1, and
the same poles as ``type: bspline`` (the same surface, non-rational). A third problem, the
NURBS quarter cylinder of ``runs/nurbs_cylinder_vega.yaml`` (true weights), is timed beside
them. Batches of random parameter sets (all nine tools, the default ranges) are evaluated
interleaved (bspline, nurbs, cylinder, bspline, ...) so that a load change on a shared host
hits all of them; the ratio of medians is the figure.
Run:  python runs/bench/nurbs_speed.py [--batch 100] [--repeats 7] [--seed 0]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import yaml  # noqa: E402

from evoplan.problems.toolpath import ToolpathProblem  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def free_form_net(n: int = 6) -> list:
    """A gently waved 6 x 6 net over 80 x 60 mm (a height field)."""
    x, y = np.meshgrid(np.linspace(0, 80, n), np.linspace(0, 60, n), indexing="ij")
    z = 6 * np.sin(x / 25) * np.cos(y / 20)
    return np.stack([x, y, z], axis=2).tolist()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--batch", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()

    net = free_form_net()
    cyl = yaml.safe_load((ROOT / "runs" / "nurbs_cylinder_vega.yaml").read_text())
    surfaces = {
        "bspline": {"type": "bspline", "poles": net},
        "nurbs_w1": {"type": "nurbs", "poles": net, "weights": np.ones((6, 6)).tolist()},
        "nurbs_cylinder": cyl["problem"]["params"]["surface"],
    }
    problems = {k: ToolpathProblem(surface=s, normalization_samples=8) for k, s in surfaces.items()}
    ref = problems["bspline"]
    rng = np.random.default_rng(args.seed)
    batches = []
    for _ in range(args.repeats):
        X = ref.xl + rng.random((args.batch, ref.n_var)) * (ref.xu - ref.xl)
        X[:, 0] = rng.integers(0, ref.n_tools, args.batch)
        batches.append(X)
    outs = {k: p.evaluate(batches[0], return_values_of=["F"]) for k, p in problems.items()}  # warm-up
    same = np.max(np.abs(outs["bspline"] - outs["nurbs_w1"]))
    times = {k: [] for k in problems}
    for X in batches:
        for k, p in problems.items():
            t = time.perf_counter()
            p.evaluate(X)
            times[k].append(time.perf_counter() - t)
    med = {k: float(np.median(v)) for k, v in times.items()}
    print(f"batch {args.batch} x {args.repeats} repeats, interleaved, one process "
          f"(shared host: compare the ratios, not the absolute times)")
    for k, m in med.items():
        print(f"  {k:15s} median {m * 1e3:8.1f} ms/batch  ({args.batch / m:6.0f} evals/s)  "
              f"ratio to bspline {m / med['bspline']:.3f}")
    print(f"  objective F, nurbs (weights 1) vs bspline, largest difference: {same:.2e}")


if __name__ == "__main__":
    main()
