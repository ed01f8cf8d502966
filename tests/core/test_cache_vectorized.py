"""The vectorized cache against the per-row dictionary cache it replaced: same runs, same hits,
with its index a dictionary, the compiled table, or the dictionary the table takes over from
in the middle of a run."""

import itertools

import numpy as np
import pytest

from evoplan import cache as cache_module
from evoplan import compiled
from evoplan.cache import DictIndex, EvaluationCache, pack
from evoplan.key_index import KeyIndex
from evoplan.operators import viral_outcome
from evoplan.config import parse_config
from evoplan.engine import run
from evoplan.runner import prepare


class RowDictCache(EvaluationCache):
    """The former implementation (one ``tobytes`` and one dictionary look-up per row): the reference."""

    def lookup(self, G):
        keys = pack(G)
        f, first, seen = np.full(len(G), np.nan), np.arange(len(G)), {}
        for i, row in enumerate(keys):
            k = row.tobytes()
            if k in self.table:
                f[i] = self.table[k][1]
            elif k in seen:
                first[i] = seen[k]
            else:
                seen[k] = i
        return keys, f, first

    def store(self, keys, f, fresh=False):
        if self.size == 0:
            return
        for row, value in zip(keys, f):
            k = row.tobytes()
            if not np.isfinite(value) or k in self.table:
                continue
            if len(self.table) >= self.size:  # full: drop the oldest entry
                del self.table[next(iter(self.table))]
            self.table[k] = (row.copy(), value)

    def __len__(self):
        return len(self.table)


@pytest.fixture(params=["never", "always", "switch"])
def index_mode(request, monkeypatch):
    """The cache's index (and VEGA's round) numpy, compiled, or numpy for the first batches
    and compiled from the fifth on (the table takes over the dictionary's entries)."""
    if request.param == "switch":
        calls = itertools.count()
        switch = lambda rows=0: next(calls) >= 5  # noqa: E731
        monkeypatch.setattr(cache_module, "use_compiled", switch)
        monkeypatch.setattr(viral_outcome, "use_compiled", switch)
        yield request.param
        return
    previous = compiled.set_mode(request.param)
    yield request.param
    compiled.set_mode(previous)


def reference(size):
    cache = RowDictCache(size)
    cache.table = {}
    return cache


def runs(algorithm: str, size: int, bits: int, gens: int = 30, population: int = 30):
    cfg = parse_config({"seed": 5, "problem": {"name": "kubota", "bits": bits},
                        "algorithm": {"name": algorithm, "population": population}, "termination": {"generations": gens},
                        "cache": {"size": size}})
    p = prepare(cfg)
    new = run(p.new_state(), p.space, p.evaluator, p.termination)
    old = p.new_state()
    old.cache = reference(size)
    old = run(old, p.space, p.evaluator, p.termination)
    return new, old


@pytest.mark.parametrize("algorithm", ["ga", "vega"])
@pytest.mark.parametrize("size, bits, population", [(100_000, 23, 30), (100_000, 5, 30), (40, 5, 30), (0, 5, 30),
                                                    (100_000, 40, 30), (100_000, 6, 150), (500, 8, 150)])
def test_same_runs_bit_for_bit_and_same_hits_as_the_row_by_row_cache(algorithm, size, bits, population,
                                                                     index_mode):
    new, old = runs(algorithm, size, bits, population=population)  # 150: batches past the dict pass
    if size and bits <= 32:  # keys of up to 8 bytes: the index the mode says
        compiled_index = isinstance(new.cache._index, KeyIndex)
        assert compiled_index == (index_mode != "never")
        assert compiled_index or isinstance(new.cache._index, DictIndex)
    strip = lambda st: [row[:8] for row in st.history]  # noqa: E731 - all but the seconds
    assert strip(new) == strip(old)
    assert new.best_f == old.best_f and (new.best_g == old.best_g).all()
    assert new.improvements == old.improvements
    assert (new.cache.hits, new.cache.misses, len(new.cache)) == (old.cache.hits, old.cache.misses, len(old.cache))
    assert new.cache.hits > 0 or size == 0 and bits > 10
    if size:  # the same entries, in the same first-in-first-out order
        kept = [row.tobytes() for row, _ in old.cache.table.values()]
        order = np.roll(np.arange(len(new.cache)), -new.cache.next) if len(new.cache) == size else np.arange(len(new.cache))
        assert [row.tobytes() for row in new.cache.keys[order]] == kept
    if algorithm == "vega":
        assert new.algorithm.infections_unchanged == old.algorithm.infections_unchanged > 0


def test_wide_genotypes_use_byte_keys_and_survive_a_checkpoint_round_trip():
    new, old = runs("ga", 50, 40)  # 80 bits: 10-byte keys
    assert new.cache.codes.dtype.kind == "V"
    copy = EvaluationCache.from_data(new.cache.to_data())
    G = new.algorithm.G
    _, f, _ = copy.lookup(G)
    _, f0, _ = new.cache.lookup(G)
    assert np.array_equal(f, f0, equal_nan=True) and len(copy) == len(new.cache) == 50
