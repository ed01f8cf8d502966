"""Speed-up of spreading one population's evaluations over Dask workers (a measurement, not a test).

An expensive black box is simulated by a sphere that sleeps 0.1 s per evaluation
(``blackboxes.Sleepy``). The same GA run (population 20, 5 generations, 100 evaluations) is
timed with the serial ``Evaluator`` and with ``ParallelEvaluator`` on a local Dask cluster of
``--workers`` workers; the best values must be identical.

    python runs/bench/parallel_evaluation.py [--workers 2] [--backend dask|processes]

(The black box lives in the test suite's package, which the script puts on the path.)
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository: tests.study

from evoplan.config import parse_config
from evoplan.engine import run
from evoplan.parallel import ParallelEvaluator, open_pool
from evoplan.runner import prepare


def timed_run(evaluator_for) -> tuple[float, float, int]:
    cfg = parse_config({"seed": 3, "problem": {"name": "tests.study.blackboxes:Sleepy", "params": {"delay": 0.1}},
                        "algorithm": {"name": "ga", "population": 20}, "termination": {"generations": 4}})
    p = prepare(cfg)
    state = p.new_state()
    evaluator = evaluator_for(p.evaluator)
    t0 = time.perf_counter()
    run(state, p.space, evaluator, p.termination)
    return time.perf_counter() - t0, state.best_f, state.evaluations


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--backend", default="dask")
    args = ap.parse_args()
    serial, best_s, n = timed_run(lambda ev: ev)
    pool = open_pool(args.backend, args.workers)
    try:
        timed_run(lambda ev: ParallelEvaluator(ev, pool))  # warm the workers (imports)
        parallel, best_p, _ = timed_run(lambda ev: ParallelEvaluator(ev, pool))
    finally:
        pool.close()
    print(f"{n} evaluations of 0.1 s: serial {serial:.2f} s, {args.backend} x{args.workers} {parallel:.2f} s, "
          f"speed-up {serial / parallel:.2f}x, same best: {best_s == best_p}")


if __name__ == "__main__":
    main()
