"""The evaluation cache: hits and misses, how they are charged, bounded memory, plain-data state."""

import pickle

import numpy as np
import pytest

from evoplan.algorithms.base import Algorithm
from evoplan.cache import EvaluationCache
from evoplan.config import parse_config
from evoplan.engine import RunState, Termination, evaluate, run
from evoplan.evaluation import Evaluation
from evoplan.runner import prepare


class Counting:
    """An evaluator of 8-bit genotypes decoded to one integer; records every row it evaluates."""

    def __init__(self, fail_at: int | None = None) -> None:
        self.rows: list[int] = []
        self.fail_at = fail_at

    def __call__(self, X: np.ndarray) -> Evaluation:
        x = X[:, 0].astype(int)
        self.rows += x.tolist()
        f = x.astype(float)
        failed = x == self.fail_at
        return Evaluation(np.where(failed, np.inf, f), failed, ["boom"] if failed.any() else [])


class Bits:
    """The space of 8-bit genotypes read as one unsigned integer."""

    n_bits = 8

    def decode(self, G: np.ndarray) -> np.ndarray:
        return (G.astype(int) @ (1 << np.arange(7, -1, -1)))[:, None]


def genotype(*values: int) -> np.ndarray:
    return np.unpackbits(np.array(values, dtype=np.uint8)[:, None], axis=1).astype(bool)


def state(budget: str = "distinct", size: int = 100) -> RunState:
    return RunState(algorithm=None, rng=np.random.default_rng(0), cache=EvaluationCache(size, budget))


@pytest.mark.parametrize("budget, charged", [("distinct", 3), ("all", 5)])
def test_a_known_genotype_is_not_evaluated_again_and_the_budget_counts_as_configured(budget, charged):
    s, ev = state(budget), Counting()
    f1 = evaluate(s, genotype(9, 4, 9), Bits(), ev)  # 9 twice in one batch: evaluated once
    f2 = evaluate(s, genotype(9, 7), Bits(), ev)  # 9 known: a hit
    assert f1.tolist() == [9, 4, 9] and f2.tolist() == [9, 7]
    assert ev.rows == [9, 4, 7]
    assert s.cache.hits == s.cache_hits == 2 and s.cache.misses == 3
    assert s.evaluations == charged


def test_improvements_are_indexed_by_evaluation_not_by_batch():
    s = state("distinct")
    evaluate(s, genotype(5, 3, 3, 4), Bits(), Counting())  # evaluations 1, 2, (hit), 3
    evaluate(s, genotype(3, 1), Bits(), Counting())  # (hit), evaluation 4
    assert s.improvements == [(1, 5.0), (2, 3.0), (4, 1.0)]
    assert s.best_f == 1.0 and Bits().decode(s.best_g[None])[0, 0] == 1
    s = state("all")
    evaluate(s, genotype(5, 3, 3, 4), Bits(), Counting())
    evaluate(s, genotype(3, 1), Bits(), Counting())
    assert s.improvements == [(1, 5.0), (2, 3.0), (6, 1.0)]


def test_a_failure_is_counted_and_retried_not_cached():
    s, ev = state(), Counting(fail_at=6)
    assert evaluate(s, genotype(6), Bits(), ev).tolist() == [np.inf]
    evaluate(s, genotype(6), Bits(), ev)
    assert ev.rows == [6, 6] and s.failures == 2 and s.errors == ["boom"] and s.evaluations == 2


def test_memory_is_bounded_first_in_first_out():
    s, ev = state(size=2), Counting()
    evaluate(s, genotype(1, 2, 3), Bits(), ev)  # 1 is dropped when 3 comes in
    evaluate(s, genotype(2, 3, 1), Bits(), ev)
    assert len(s.cache) == 2 and ev.rows == [1, 2, 3, 1]
    assert s.cache.values.size == 2


def test_the_cache_is_plain_data_and_survives_a_round_trip():
    s, ev = state(size=3), Counting()
    evaluate(s, genotype(1, 2, 3, 4), Bits(), ev)
    data = s.cache.to_data()
    assert all(isinstance(v, (int, str, np.ndarray)) for v in data.values())
    for copy in (EvaluationCache.from_data(data), pickle.loads(pickle.dumps(s.cache))):
        _, f, _ = copy.lookup(genotype(1, 2, 3, 4))
        assert np.isnan(f[0]) and f[1:].tolist() == [2, 3, 4]
        assert (copy.hits, copy.misses, copy.next) == (s.cache.hits, s.cache.misses, s.cache.next)
    empty = EvaluationCache.from_data(EvaluationCache(5).to_data())
    assert len(empty) == 0


def kubota(algorithm: str, **cache):
    cfg = parse_config({"seed": 3, "problem": {"name": "kubota", "bits": 6},
                        "algorithm": {"name": algorithm, "population": 10}, "termination": {"generations": 25},
                        "cache": cache})
    return prepare(cfg)


@pytest.mark.parametrize("algorithm", ["ga", "vega"])
def test_budget_all_gives_the_numbers_of_a_run_without_cache(algorithm):
    p = kubota(algorithm, budget="all")
    cached = run(p.new_state(), p.space, p.evaluator, p.termination)
    plain = p.new_state()
    plain.cache = None
    plain = run(plain, p.space, p.evaluator, p.termination)
    strip = lambda st: [row[:7] for row in st.history]  # noqa: E731 - all but hits and seconds
    assert strip(cached) == strip(plain) and cached.best_f == plain.best_f
    assert cached.cache_hits > 0 and cached.cache.misses < cached.evaluations


def test_the_ga_saves_evaluations_on_a_small_codec():
    p = kubota("ga")  # 12-bit genotypes: the population soon repeats itself
    s = run(p.new_state(), p.space, p.evaluator, p.termination)
    assert s.cache_hits > 0.2 * (s.evaluations + s.cache_hits)
    assert s.history[-1][1] == s.evaluations == s.cache.misses


class Stuck(Algorithm):
    """Asks for the same genotype forever."""

    def ask(self):
        return np.zeros((4, self.n_bits), bool)

    def tell(self, f):
        self.generation += 1
        self.f = np.asarray(f)
        return True


def test_a_run_that_finds_nothing_new_stops_as_stalled():
    s = RunState(algorithm=Stuck(8, np.random.default_rng(0)), rng=np.random.default_rng(0),
                 cache=EvaluationCache(10, "distinct", stall_generations=5))
    run(s, Bits(), Counting(), Termination(evaluations=100))
    assert s.stop_reason == "stalled" and s.evaluations == 1 and s.algorithm.generation == 5
