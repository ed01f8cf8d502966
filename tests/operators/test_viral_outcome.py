"""VEGA's infection round: the compiled form against the numpy form, bit for bit."""

import numpy as np
import pytest

from evoplan import compiled
from evoplan.operators import viral
from evoplan.operators.viral_kernels import infection_outcome as compiled_outcome
from evoplan.operators.viral_outcome import infect_pairs, infection_outcome, outcome_matrices


@pytest.fixture(params=["always", "never"])
def mode(request):
    previous = compiled.set_mode(request.param)
    yield request.param
    compiled.set_mode(previous)


def random_round(seed):
    rng = np.random.default_rng(seed)
    V, N = int(rng.integers(1, 8)), int(rng.integers(1, 40))
    virus, host = np.nonzero(rng.random((V, N)) < rng.uniform(0.05, 0.9))  # sorted by virus
    f_host = rng.integers(0, 5, N).astype(float)  # ties, so "first" matters
    f_host[rng.random(N) < 0.1] = np.inf  # failed hosts
    f = np.where(rng.random(virus.size) < 0.5, f_host[host], rng.integers(0, 5, virus.size))
    f[rng.random(virus.size) < 0.1] = np.inf  # failed trials
    if seed % 5 == 0 and f.size:
        f[0] = np.nan
    return virus, host, f != f_host[host], f, f_host, V


@pytest.mark.parametrize("improve", [True, False])
@pytest.mark.parametrize("seed", range(20))
def test_the_compiled_outcome_is_the_matrix_form_bit_for_bit(seed, improve):
    virus, host, changed, f, f_host, V = random_round(seed)
    got = compiled_outcome(virus, host, changed, f, f_host, V, improve)
    want = outcome_matrices(virus, host, changed, f, f_host, V, improve)
    take = want[0]
    np.testing.assert_array_equal(got[0], take)
    np.testing.assert_array_equal(got[1][take], want[1][take])  # the best, where it is used
    np.testing.assert_array_equal(got[2][take], want[2][take])
    assert got[3].tobytes() == want[3].tobytes()  # Eq. 12 summed in the same order
    np.testing.assert_array_equal(got[4], want[4])
    np.testing.assert_array_equal(got[5], want[5])


def test_the_outcome_takes_each_hosts_first_best_and_each_viruses_best_gain(mode):
    # virus 0 infects hosts 0, 1; virus 1 infects hosts 0, 2; f_host = 5, 5, 5
    virus, host = np.array([0, 0, 1, 1]), np.array([0, 1, 0, 2])
    f = np.array([3.0, 6.0, 3.0, 1.0])
    take, best, best_f, fitvirus, infected, best_pair = infection_outcome(
        virus, host, np.ones(4, bool), f, np.full(3, 5.0), 3, True)
    np.testing.assert_array_equal(take, [True, False, True])  # host 1's trial is worse
    assert best[0] == 0 and best[2] == 3  # host 0: the tie 3 = 3 goes to the first virus
    np.testing.assert_array_equal(best_f[take], [3.0, 1.0])
    np.testing.assert_array_equal(fitvirus, [2.0 - 1.0, 2.0 + 4.0, 0.0])  # Eq. 11-12
    np.testing.assert_array_equal(infected, [True, True, False])
    np.testing.assert_array_equal(best_pair, [0, 3, -1])


@pytest.mark.parametrize("seed", range(10))
def test_infection_is_reverse_transcription(seed, mode):
    rng = np.random.default_rng(seed)
    V, N, L = 5, 30, 46
    G = (rng.random((3, L)) < 0.5)[rng.integers(0, 3, N)]  # hosts repeat: some infections change nothing
    start, length, bits = viral.transduction(G[rng.integers(0, N, V)], 12, rng)
    virus, host = np.nonzero(rng.random((V, N)) < 0.3)
    trials, changed = infect_pairs(G, host, virus, start, length, bits)
    expected = G[host].copy()
    for p in range(virus.size):  # one pair at a time, as Fig. 3b draws it
        v = virus[p]
        expected[p, start[v]:start[v] + length[v]] = bits[v, start[v]:start[v] + length[v]]
    np.testing.assert_array_equal(trials, expected)
    np.testing.assert_array_equal(changed, (expected != G[host]).any(axis=1))
    assert changed.any() and not changed.all()  # both kinds occur: the test can tell them apart
