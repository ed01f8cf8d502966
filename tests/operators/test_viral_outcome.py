"""The compiled infection outcome against the (virus x host) matrix form it replaces."""

import numpy as np
import pytest

from evoplan.operators import viral
from evoplan.operators.viral_outcome import infect_pairs, infection_outcome


def matrix_form(virus, host, changed, f, f_host, V, improve):
    """Rule 3 and Eq. 11-12 as numpy matrices: argmin over viruses, bincount, argmax."""
    N = f_host.size
    trial = np.full((V, N), -1)
    trial[virus, host] = np.arange(virus.size)
    F = np.full((V, N), np.inf)
    F[virus, host] = f
    pair_gain = np.where(changed, viral.infection_gain(f_host[host], f), 0.0)
    gain = np.zeros((V, N))
    gain[virus, host] = pair_gain
    best_virus = F.argmin(axis=0)
    best = trial[best_virus, np.arange(N)]
    best_f = F[best_virus, np.arange(N)]
    take = (best >= 0) & np.isfinite(best_f)
    if improve:
        take &= best_f < f_host
    best_host = np.where(trial >= 0, gain, -np.inf).argmax(axis=1)
    infected = (trial >= 0).any(axis=1)
    best_pair = np.where(infected, trial[np.arange(V), best_host], -1)
    return take, best, best_f, viral.virus_fitness(pair_gain, virus, V), infected, best_pair


@pytest.mark.parametrize("improve", [True, False])
@pytest.mark.parametrize("seed", range(20))
def test_the_compiled_outcome_is_the_matrix_form_bit_for_bit(seed, improve):
    rng = np.random.default_rng(seed)
    V, N = int(rng.integers(1, 8)), int(rng.integers(1, 40))
    virus, host = np.nonzero(rng.random((V, N)) < rng.uniform(0.05, 0.9))  # sorted by virus
    f_host = rng.integers(0, 5, N).astype(float)  # ties, so "first" matters
    f_host[rng.random(N) < 0.1] = np.inf  # failed hosts
    f = np.where(rng.random(virus.size) < 0.5, f_host[host], rng.integers(0, 5, virus.size))
    f[rng.random(virus.size) < 0.1] = np.inf  # failed trials
    if seed % 5 == 0 and f.size:
        f[0] = np.nan
    changed = f != f_host[host]
    got = infection_outcome(virus, host, changed, f, f_host, V, improve)
    want = matrix_form(virus, host, changed, f, f_host, V, improve)
    take = want[0]
    np.testing.assert_array_equal(got[0], take)
    np.testing.assert_array_equal(got[1][take], want[1][take])  # the best, where it is used
    np.testing.assert_array_equal(got[2][take], want[2][take])
    assert got[3].tobytes() == want[3].tobytes()  # Eq. 12 summed in the same order
    np.testing.assert_array_equal(got[4], want[4])
    np.testing.assert_array_equal(got[5], want[5])


@pytest.mark.parametrize("seed", range(10))
def test_compiled_infection_is_reverse_transcription(seed):
    rng = np.random.default_rng(seed)
    V, N, L = 5, 30, 46
    G = (rng.random((3, L)) < 0.5)[rng.integers(0, 3, N)]  # hosts repeat: some infections change nothing
    start, length, bits = viral.transduction(G[rng.integers(0, N, V)], 12, rng)
    virus, host = np.nonzero(rng.random((V, N)) < 0.3)
    trials, changed = infect_pairs(G, host, virus, start, length, bits)
    np.testing.assert_array_equal(trials, viral.infect(G, host, virus, start, length, bits))
    np.testing.assert_array_equal(changed, (trials != G[host]).any(axis=1))
    assert changed.any() and not changed.all()  # both kinds occur: the test can tell them apart
