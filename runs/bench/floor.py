"""The numpy floor: a plain numpy GA loop against evoplan's GA and VEGA, in one process.

The floor is the least a GA on Kubota's function (Fountas Eq. 13, 46 bits, Eq. 8 decoding)
can cost in numpy: Eq. 10 exponential fitness on ranks, roulette, single-point crossover,
single-point mutation, one elite, a whole population evaluated in one vectorized call. It
draws from its generator in the order evoplan's GA does, so with the same seed it reaches the
same best value (printed as a check). evoplan's GA and VEGA run the same sizes through the
run engine (`evoplan.runner.prepare` + `evoplan.engine.run`, the evaluation cache on, as
`evoplan run` does, without a results folder). The three are interleaved over ``--repeat``
rounds and the ratios are medians of the per-round ratios of process CPU time (the host may
be shared: CPU time is less disturbed by other processes than wall time).

evoplan's cache index, the GA's breeding pass and VEGA's infection round each have a numpy
and a compiled form (``evoplan/compiled.py`` says which a run takes): ``--compiled both``
(the default) times each of GA and VEGA in both forms in the same rounds, and prints beside
them what loading numba and dispatching the compiled forms costs once, in a fresh interpreter.

    python runs/bench/floor.py [--repeat 7] [--sizes 200x200,2000x40] [--compiled both|always|never]

Not a test: it prints measured figures.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time

import numpy as np

from evoplan import compiled
from evoplan.config import parse_config
from evoplan.engine import run
from evoplan.runner import prepare

BITS = 23
W = 2.0 ** np.arange(BITS - 1, -1, -1)
SCALE = 2.0 / (2**BITS - 1)


def kubota(G: np.ndarray) -> np.ndarray:
    x = -1 + (G[:, :BITS] @ W) * SCALE
    y = -1 + (G[:, BITS:] @ W) * SCALE
    return x**2 + y**2 - 0.3 * np.cos(3 * np.pi * x) - 0.4 * np.cos(4 * np.pi * y) + 0.7


def floor_ga(pop: int, gens: int, seed: int) -> float:
    """The plain loop: evoplan GA's defaults (rank, pressure 2, roulette, 0.9, 0.5, 1 elite)."""
    rng = np.random.default_rng(seed)
    L = 2 * BITS
    G = rng.random((pop, L)) < 0.5
    f = kubota(G.astype(np.float64))
    best = f.min()
    n_child = pop - 1
    n_pairs = (n_child + 1) // 2
    pos = np.arange(L)
    ranks = np.empty(pop)
    for _ in range(gens):
        order = np.argsort(f, kind="stable")
        elite = order[:1]
        ranks[order] = np.arange(pop)
        v = ranks / (pop - 1) * 2.0
        cum = np.cumsum(np.abs(f).sum() * np.exp(-(v * v)))
        parents = np.minimum(np.searchsorted(cum, rng.random(2 * n_pairs) * cum[-1], side="right"), pop - 1)
        A, B = G[parents[:n_pairs]], G[parents[n_pairs:]]
        cut = rng.integers(1, L, n_pairs)
        cross = rng.random(n_pairs) < 0.9
        mask = (pos >= cut[:, None]) & cross[:, None]
        D = (A ^ B) & mask  # the bits the pair swaps (as fast as numpy swaps booleans)
        children = np.concatenate([A ^ D, B ^ D])[:n_child]
        hit = np.flatnonzero(rng.random(n_child) < 0.5)
        loci = rng.integers(0, L, n_child)[hit]
        children[hit, loci] ^= True
        fc = kubota(children.astype(np.float64))
        best = min(best, fc.min())
        G = np.concatenate([G[elite], children])
        f = np.concatenate([f[elite], fc])
    return float(best)


def evoplan_run(name: str, pop: int, gens: int, seed: int, cache: bool = True):
    cfg = parse_config({
        "seed": seed,
        "problem": {"name": "kubota", "bits": BITS},
        "algorithm": {"name": name, "population": pop},
        "termination": {"generations": gens},
        "cache": {"size": 100_000 if cache else 0},
    })
    p = prepare(cfg)
    state = p.new_state()
    return run(state, p.space, p.evaluator, p.termination)


def timed(fn, *args):
    """CPU seconds of this process (less disturbed by a shared host than wall time) and the result."""
    t0 = time.process_time()
    out = fn(*args)
    return time.process_time() - t0, out


LOAD = """
import time
import numpy as np
from evoplan import compiled
from evoplan.cache import EvaluationCache
from evoplan.operators.viral_outcome import infect_pairs, infection_outcome
compiled.set_mode("always")
t0 = time.process_time()
G = np.random.default_rng(0).random((50, 46)) < 0.5
cache = EvaluationCache(100)
keys, _, _ = cache.lookup(G)
cache.store(keys, np.zeros(50))
v, h = np.array([0, 1]), np.array([3, 4])
trials, changed = infect_pairs(G, h, v, np.array([0, 2]), np.array([3, 3]), G[:2].copy())
infection_outcome(v, h, changed, np.zeros(2), np.zeros(50), 2, True)
keys, f, first, todo = cache.pending(G)
from evoplan.operators.breeding import breed
breed(G, v, h, np.array([3, 46]), np.array([46, 46]), np.array([1, -1, 5]), 3)
print(time.process_time() - t0)
"""


def numba_load_seconds() -> float:
    """CPU seconds a fresh interpreter spends loading numba and dispatching the core's
    compiled forms (from numba's on-disk cache) the first time."""
    out = subprocess.run([sys.executable, "-c", LOAD], capture_output=True, text=True, check=True)
    return float(out.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--sizes", default="200x200,2000x40", help="POPxGENERATIONS, comma-separated")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--compiled", choices=("both", "always", "never"), default="both",
                    help="the forms of the cache index and VEGA's round to time")
    args = ap.parse_args()
    modes = ("never", "always") if args.compiled == "both" else (args.compiled,)
    print("process CPU seconds; ratios are medians over interleaved rounds in this one process")
    if "always" in modes:
        loads = [numba_load_seconds() for _ in range(3)]
        print(f"loading numba + the first dispatch of the compiled forms, fresh interpreter: "
              f"{np.median(loads):.2f} s (of 3: {', '.join(f'{x:.2f}' for x in loads)})")
    for size in args.sizes.split(","):
        pop, gens = map(int, size.lower().split("x"))
        t_floor, t = [], {(m, a): [] for m in modes for a in ("ga", "vega")}
        for mode in modes:  # warm-up
            compiled.set_mode(mode)
            evoplan_run("ga", 20, 2, 0), evoplan_run("vega", 20, 2, 0), floor_ga(20, 2, 0)
        for r in range(args.repeat):
            seed = args.seed + r
            tf, best_floor = timed(floor_ga, pop, gens, seed)
            t_floor.append(tf)
            for mode in modes:
                compiled.set_mode(mode)
                for algorithm in ("ga", "vega"):
                    dt, state = timed(evoplan_run, algorithm, pop, gens, seed)
                    t[mode, algorithm].append(dt)
                    if algorithm == "ga" and best_floor != state.best_f:
                        print(f"  warning: seed {seed}: floor best {best_floor!r} != evoplan GA best "
                              f"{state.best_f!r}")
        compiled.set_mode("auto")
        tf = np.asarray(t_floor)
        print(f"pop {pop} x {gens} generations, {args.repeat} rounds:")
        print(f"  floor            median {np.median(tf):.4f} s")
        for mode in modes:
            tg, tv = np.asarray(t[mode, "ga"]), np.asarray(t[mode, "vega"])
            form = "numpy" if mode == "never" else "compiled"
            print(f"  GA, {form:8s}    median {np.median(tg):.4f} s   GA/floor  median "
                  f"{np.median(tg / tf):.2f}x (range {np.min(tg / tf):.2f}-{np.max(tg / tf):.2f})")
            print(f"  VEGA, {form:8s}  median {np.median(tv):.4f} s   VEGA/GA   median "
                  f"{np.median(tv / tg):.2f}x (range {np.min(tv / tg):.2f}-{np.max(tv / tg):.2f})")


if __name__ == "__main__":
    main()
