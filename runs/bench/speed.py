"""Framework overhead on a cheap function: evoplan GA/VEGA against DEAP eaSimple and pymoo GA.

The same problem for all: Kubota's function (Fountas Eq. 13) on a 46-bit chromosome (23 bits
per variable, Eq. 8), population 200, 200 generations, single-point crossover, bit-flip style
mutation, one process. Each library is used the way its documentation shows; the evaluation
counts differ slightly (DEAP re-evaluates only changed individuals, evoplan does not re-evaluate
its elite), so the time per evaluation is reported beside the wall time.

    python runs/bench/speed.py [--repeat 5] [--pop 200] [--gens 200]

Not a test: it prints a table of measured figures.
"""

from __future__ import annotations

import argparse
import random
import tempfile
import time
from pathlib import Path

import numpy as np

from evoplan.config import parse_config
from evoplan.engine import Checkpointer, run
from evoplan.runner import prepare


def kubota_bits(bits: np.ndarray) -> np.ndarray:
    """Eq. 8 decoding of (n, 46) bits then Eq. 13, for the other libraries."""
    w = 2.0 ** np.arange(22, -1, -1)
    x = -1 + bits[:, :23] @ w * 2 / (2**23 - 1)
    y = -1 + bits[:, 23:] @ w * 2 / (2**23 - 1)
    return x**2 + y**2 - 0.3 * np.cos(3 * np.pi * x) - 0.4 * np.cos(4 * np.pi * y) + 0.7


def evoplan_run(name: str, pop: int, gens: int, seed: int, checkpoint: bool) -> tuple[float, int, float]:
    cfg = parse_config({
        "seed": seed,
        "problem": {"name": "kubota", "bits": 23},
        "algorithm": {"name": name, "population": pop},
        "termination": {"generations": gens},
    })
    p = prepare(cfg)
    with tempfile.TemporaryDirectory() as tmp:
        # the default checkpoint policy of `evoplan run` (every 30 s and at the end)
        ckpt = Checkpointer(Path(tmp) / "c.pkl", cfg.checkpoint.every_generations, cfg.checkpoint.every_seconds)
        t0 = time.perf_counter()
        state = run(p.new_state(), p.space, p.evaluator, p.termination, ckpt if checkpoint else None)
        return time.perf_counter() - t0, state.evaluations, state.best_f


def deap_run(pop: int, gens: int, seed: int) -> tuple[float, int, float]:
    from deap import algorithms, base, creator, tools

    if not hasattr(creator, "FitnessMinSpeed"):
        creator.create("FitnessMinSpeed", base.Fitness, weights=(-1.0,))
        creator.create("IndividualSpeed", list, fitness=creator.FitnessMinSpeed)
    random.seed(seed)
    count = [0]

    def evaluate(ind):
        count[0] += 1
        return (float(kubota_bits(np.array(ind, dtype=float)[None, :])[0]),)

    tb = base.Toolbox()
    tb.register("bit", random.randint, 0, 1)
    tb.register("individual", tools.initRepeat, creator.IndividualSpeed, tb.bit, 46)
    tb.register("population", tools.initRepeat, list, tb.individual)
    tb.register("evaluate", evaluate)
    tb.register("mate", tools.cxOnePoint)
    tb.register("mutate", tools.mutFlipBit, indpb=1 / 46)
    tb.register("select", tools.selTournament, tournsize=2)
    hof = tools.HallOfFame(1)
    t0 = time.perf_counter()
    population = tb.population(n=pop)
    algorithms.eaSimple(population, tb, cxpb=0.9, mutpb=0.5, ngen=gens, halloffame=hof, verbose=False)
    return time.perf_counter() - t0, count[0], hof[0].fitness.values[0]


def pymoo_run(pop: int, gens: int, seed: int, eliminate_duplicates: bool) -> tuple[float, int, float]:
    from pymoo.algorithms.soo.nonconvex.ga import GA
    from pymoo.core.problem import Problem
    from pymoo.operators.crossover.pntx import SinglePointCrossover
    from pymoo.operators.mutation.bitflip import BitflipMutation
    from pymoo.operators.sampling.rnd import BinaryRandomSampling
    from pymoo.optimize import minimize

    class Kubota46(Problem):
        def __init__(self):
            super().__init__(n_var=46, n_obj=1, xl=0, xu=1, vtype=bool)

        def _evaluate(self, X, out, *args, **kwargs):
            out["F"] = kubota_bits(X.astype(float))[:, None]

    algorithm = GA(pop_size=pop, sampling=BinaryRandomSampling(), crossover=SinglePointCrossover(),
                   mutation=BitflipMutation(), eliminate_duplicates=eliminate_duplicates)
    t0 = time.perf_counter()
    res = minimize(Kubota46(), algorithm, ("n_gen", gens), seed=seed, verbose=False)
    return time.perf_counter() - t0, res.algorithm.evaluator.n_eval, float(res.F[0])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--pop", type=int, default=200)
    ap.add_argument("--gens", type=int, default=200)
    args = ap.parse_args()
    for name in ("ga", "vega"):  # warm imports and first-call costs before anything is timed
        evoplan_run(name, 20, 5, 0, True)
    contenders = {
        "evoplan GA (no checkpoint)": lambda s: evoplan_run("ga", args.pop, args.gens, s, False),
        "evoplan GA (default checkpoint)": lambda s: evoplan_run("ga", args.pop, args.gens, s, True),
        "evoplan VEGA (default checkpoint)": lambda s: evoplan_run("vega", args.pop, args.gens, s, True),
        "DEAP eaSimple": lambda s: deap_run(args.pop, args.gens, s),
        "pymoo GA (eliminate_duplicates=False)": lambda s: pymoo_run(args.pop, args.gens, s, False),
        "pymoo GA (eliminate_duplicates=True, its default)": lambda s: pymoo_run(args.pop, args.gens, s, True),
    }
    rows = {}
    for name, fn in contenders.items():
        times, evals, best = [], [], []
        for rep in range(args.repeat):
            t, n, b = fn(rep + 1)
            times.append(t), evals.append(n), best.append(b)
        rows[name] = (min(times), int(np.mean(evals)), float(np.median(best)))
    ga = rows["evoplan GA (default checkpoint)"]
    print(f"Kubota 46 bits, population {args.pop}, {args.gens} generations, best of {args.repeat} runs")
    print(f"{'':50s} {'wall s':>9s} {'evals':>7s} {'us/eval':>8s} {'x GA':>7s} {'x GA/eval':>9s} {'median best':>12s}")
    for name, (t, n, b) in rows.items():
        print(f"{name:50s} {t:9.4f} {n:7d} {1e6 * t / n:8.2f} {t / ga[0]:7.1f} {(t / n) / (ga[0] / ga[1]):9.1f} {b:12.3g}")
    vega, plain = rows["evoplan VEGA (default checkpoint)"], rows["evoplan GA (no checkpoint)"]
    print(f"checkpoint overhead: {100 * (ga[0] / plain[0] - 1):+.1f} %")
    print(f"VEGA / GA time per generation: {vega[0] / ga[0]:.2f}")


if __name__ == "__main__":
    main()
