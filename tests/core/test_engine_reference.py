"""Runs recorded before the core was sped up: the same runs, bit for bit, with the same hits.

``data/engine_reference.json`` holds, for GA and VEGA runs of several sizes, cache settings and
operators, the evaluation and hit counts, the best value and a SHA-256 digest of everything else
a run produces (history rows but their seconds, improvements, best genotype, final population,
generator state, the cache's entries in first-in-first-out order). It was written by this
module (``python -m tests.core.test_engine_reference --record``) from the code before the
vectorized cache and engine changes; re-record only on a deliberate change of the numbers.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from evoplan import compiled
from evoplan.config import parse_config
from evoplan.engine import run
from evoplan.runner import prepare

DATA = Path(__file__).with_name("data") / "engine_reference.json"

# (name, algorithm, bits per variable, population, generations, cache settings, algorithm settings)
CASES = [
    ("ga-23-30", "ga", 23, 30, 40, {}, {}),
    ("vega-23-30", "vega", 23, 30, 40, {}, {}),
    ("ga-floor-200", "ga", 23, 200, 30, {}, {}),
    ("vega-floor-200", "vega", 23, 200, 30, {}, {}),
    ("ga-2000", "ga", 23, 2000, 4, {}, {}),
    ("vega-2000", "vega", 23, 2000, 3, {}, {}),
    ("ga-5-fifo", "ga", 5, 30, 40, {"size": 40}, {}),
    ("vega-5-fifo", "vega", 5, 30, 40, {"size": 40}, {}),
    ("ga-6-150", "ga", 6, 150, 30, {}, {}),
    ("vega-8-150-fifo", "vega", 8, 150, 30, {"size": 500}, {}),
    ("ga-bytes", "ga", 40, 30, 30, {}, {}),
    ("vega-bytes", "vega", 40, 30, 30, {"size": 200}, {}),
    ("ga-nocache", "ga", 5, 30, 30, {"size": 0}, {}),
    ("vega-nocache", "vega", 5, 30, 30, {"size": 0}, {}),
    ("ga-budget-all", "ga", 5, 30, 30, {"budget": "all"}, {}),
    ("vega-budget-all", "vega", 5, 30, 30, {"budget": "all"}, {}),
    ("ga-operators", "ga", 10, 40, 30, {}, {"elitism": 3, "fitness": {"normalize": "minmax", "pressure": 1.5},
                                              "selection": {"kind": "tournament", "size": 3},
                                              "crossover": {"kind": "two_point", "rate": 0.7},
                                              "mutation": {"kind": "per_bit", "rate": 0.02}}),
    ("vega-kubota-rule", "vega", 10, 40, 30, {}, {"elitism": 2, "virus": {"life_rule": "kubota", "count": 5,
                                                                            "infect_every": 2, "replacement": "always"}}),
]


def execute(algorithm: str, bits: int, population: int, generations: int, cache: dict, settings: dict):
    cfg = parse_config({"seed": 11, "problem": {"name": "kubota", "bits": bits},
                        "algorithm": {"name": algorithm, "population": population, **settings},
                        "termination": {"generations": generations}, "cache": cache})
    p = prepare(cfg)
    return run(p.new_state(), p.space, p.evaluator, p.termination)


def summary(state) -> dict:
    """The counts in the clear and a digest of everything else the run produced."""
    h = hashlib.sha256()
    h.update(repr([row[:8] for row in state.history]).encode())
    h.update(repr(state.improvements).encode())
    h.update(np.ascontiguousarray(state.best_g).tobytes())
    h.update(np.ascontiguousarray(state.algorithm.G).tobytes() + np.ascontiguousarray(state.algorithm.f).tobytes())
    h.update(repr(state.algorithm.rng.bit_generator.state).encode())
    cache = state.cache
    out = {"evaluations": state.evaluations, "cache_hits": state.cache_hits, "best_f": repr(state.best_f),
           "generations": state.algorithm.generation, "stop_reason": state.stop_reason}
    if cache is not None:
        n = len(cache)
        order = np.roll(np.arange(n), -cache.next) if n == cache.size else np.arange(n)
        h.update(cache.keys[order].tobytes() + cache.values[:n][order].tobytes())
        out.update(hits=cache.hits, misses=cache.misses, stored=n)
    if state.algorithm.name == "vega":
        out["infections_unchanged"] = state.algorithm.infections_unchanged
        out["infections_made"] = state.algorithm.infections_made
    out["digest"] = h.hexdigest()
    return out


def record() -> None:
    DATA.parent.mkdir(exist_ok=True)
    table = {name: summary(execute(*args)) for name, *args in CASES}
    DATA.write_text(json.dumps(table, indent=1, sort_keys=True) + "\n")


@pytest.mark.parametrize("mode", ["never", "always"])
@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_same_run_bit_for_bit_as_recorded(case, mode):
    """Both forms of the core's loops (numpy, compiled: :mod:`evoplan.compiled`) give the run."""
    name, *args = case
    expected = json.loads(DATA.read_text())[name]
    with compiled.forced(mode):
        assert summary(execute(*args)) == expected


def test_the_reference_covers_hits_fifo_drops_and_skipped_infections():
    table = json.loads(DATA.read_text())
    assert all(v["hits"] > 0 for k, v in table.items() if "nocache" not in k)
    assert table["ga-5-fifo"]["stored"] == 40 < table["ga-5-fifo"]["misses"]  # entries were dropped
    assert all(v["infections_unchanged"] > 0 for k, v in table.items() if k.startswith("vega"))
    assert table["ga-budget-all"]["evaluations"] == 30 * 30  # hits charged: every genotype asked (30 batches of 30)


if __name__ == "__main__" and "--record" in sys.argv:
    record()
