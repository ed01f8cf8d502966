import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from evoplan.operators import viral

hosts_st = st.tuples(st.integers(1, 10), st.integers(1, 60)).flatmap(
    lambda s: st.tuples(arrays(bool, s), st.integers(1, 70), st.integers(0, 2**32 - 1))
)


@settings(max_examples=80, deadline=None)
@given(hosts_st)
def test_transduction_copies_exactly_a_host_substring(case):
    hosts, max_len, seed = case
    V, L = hosts.shape
    start, length, bits = viral.transduction(hosts, max_len, np.random.default_rng(seed))
    assert ((length >= 1) & (length <= min(max_len, L))).all()
    assert ((start >= 0) & (start + length <= L)).all()
    mask = viral.loci_mask(start, length, L)
    assert (mask.sum(axis=1) == length).all()
    assert np.array_equal(bits[mask], hosts[mask])  # a substring of its host, bit for bit
    assert not bits[~mask].any()


@settings(max_examples=80, deadline=None)
@given(hosts_st, st.integers(0, 2**32 - 1))
def test_reverse_transcription_writes_exactly_the_virus_loci(case, seed2):
    hosts, max_len, seed = case
    rng = np.random.default_rng(seed2)
    donors = rng.random(hosts.shape) < 0.5
    start, length, bits = viral.transduction(donors, max_len, np.random.default_rng(seed))
    infected = viral.reverse_transcription(hosts, start, length, bits)
    mask = viral.loci_mask(start, length, hosts.shape[1])
    assert infected.shape == hosts.shape and infected.dtype == bool
    assert np.array_equal(infected[mask], donors[mask])
    assert np.array_equal(infected[~mask], hosts[~mask])


@settings(max_examples=80, deadline=None)
@given(hosts_st, st.integers(1, 5))
def test_partial_transduction_grows_up_to_the_limit(case, growth):
    hosts, max_len, seed = case
    V, L = hosts.shape
    rng = np.random.default_rng(seed)
    start, length, bits = viral.transduction(rng.random((V, L)) < 0.5, max_len, rng)
    s2, n2, b2 = viral.partial_transduction(start, length, bits, hosts, max_len, rng, growth)
    cap = min(max_len, L)
    assert np.array_equal(n2, np.maximum(np.minimum(length + growth, cap), length))
    assert ((s2 >= 0) & (s2 + n2 <= L)).all()
    old, new = viral.loci_mask(start, length, L), viral.loci_mask(s2, n2, L)
    assert np.array_equal(b2[new & old], bits[new & old])  # kept loci keep the virus' bits
    assert np.array_equal(b2[new & ~old], hosts[new & ~old])  # new loci come from the host
    assert not b2[~new].any()


def test_virus_fitness_is_the_sum_of_host_improvements():
    # three viruses; virus 0 infects hosts with objectives 5 -> 3 and 4 -> 4.5, virus 2 one host 1 -> 0.25
    f_before = np.array([5.0, 4.0, 1.0])
    f_after = np.array([3.0, 4.5, 0.25])
    gain = viral.infection_gain(f_before, f_after)
    np.testing.assert_allclose(gain, [2.0, -0.5, 0.75])
    fit = viral.virus_fitness(gain, np.array([0, 0, 2]), 3)
    np.testing.assert_allclose(fit, [1.5, 0.0, 0.75])


def test_failed_infection_counts_as_no_gain():
    gain = viral.infection_gain(np.array([1.0, np.inf]), np.array([np.inf, 2.0]))
    np.testing.assert_array_equal(gain, [0.0, 0.0])


def test_life_and_infection_rate_rules():
    life = viral.update_life(np.array([1.0, 1.0]), np.array([0.5, -2.0]), 0.1)
    np.testing.assert_allclose(life, [0.6, -1.9])
    rate = viral.adapt_infection_rate(np.array([0.7, 0.7, 0.95, 0.12]), np.array([1.0, -1.0, 1.0, -1.0]),
                                      0.1, 0.1, 1.0)
    np.testing.assert_allclose(rate, [0.77, 0.63, 1.0, 0.108])
    assert viral.adapt_infection_rate(np.array([0.5]), np.array([0.0]), 0.1, 0.2, 0.8)[0] == pytest.approx(0.5)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 8), st.integers(1, 20), st.integers(1, 50), st.integers(0, 2**32 - 1))
def test_batched_infection_equals_pairwise_reverse_transcription(V, N, L, seed):
    rng = np.random.default_rng(seed)
    G = rng.random((N, L)) < 0.5
    start, length, bits = viral.transduction(rng.random((V, L)) < 0.5, L, rng)
    virus, host = np.nonzero(rng.random((V, N)) < 0.6)
    expected = viral.reverse_transcription(G[host], start[virus], length[virus], bits[virus])
    assert np.array_equal(viral.infect(G, host, virus, start, length, bits), expected)


@pytest.mark.parametrize("L, max_length, growth", [(46, 40, 1), (46, 10, 3), (8, 8, 2), (1, 1, 1), (30, 50, 5)])
def test_compiled_transductions_equal_the_numpy_forms(L, max_length, growth):
    """Transduction and partial transduction in both forms of :mod:`evoplan.compiled`: the same
    windows, bits and generator numbers, windows at the host's ends and at the cap included."""
    from evoplan import compiled

    for seed in range(20):
        hosts = np.random.default_rng(seed).random((9, L)) < 0.5
        outs = []
        for mode in ("never", "always"):
            with compiled.forced(mode):
                rng = np.random.default_rng(seed)
                s, n, b = viral.transduction(hosts, max_length, rng)
                grown = viral.partial_transduction(s, n, b, hosts[::-1].copy(), max_length, rng, growth)
                outs.append((s, n, b, *grown, rng.random()))
        for x, y in zip(*outs):
            assert np.array_equal(x, y) and np.asarray(x).dtype == np.asarray(y).dtype


@pytest.mark.parametrize("V, N", [(7, 200), (1, 1), (3, 2000), (10, 5)])
def test_compiled_infection_pairs_equal_nonzero(V, N):
    from evoplan.operators.viral_kernels import pairs_below

    rng = np.random.default_rng(V * N)
    for rate in (rng.random(V), np.zeros(V), np.ones(V)):
        u = rng.random((V, N))
        virus, host = pairs_below(u, rate)
        expected = np.nonzero(u < rate[:, None])
        assert np.array_equal(virus, expected[0]) and np.array_equal(host, expected[1])


@pytest.mark.parametrize("kubota_rule", [False, True])
def test_compiled_life_and_rate_equal_the_numpy_rules(kubota_rule):
    from evoplan.operators.viral_kernels import life_and_rate

    rng = np.random.default_rng(int(kubota_rule))
    for _ in range(50):
        V = int(rng.integers(1, 12))
        life = rng.normal(size=V) * rng.choice([0.0, 1.0], V)
        fitvirus = rng.normal(size=V) * rng.choice([0.0, 1.0], V)  # gains, losses and none
        rate, infected = rng.uniform(0.05, 1.0, V), rng.random(V) < 0.5
        new_life = viral.update_life(life, fitvirus, 0.01)
        new_rate = viral.adapt_infection_rate(rate, fitvirus, 0.1, 0.1, 1.0)
        if kubota_rule:
            renew = new_life < 0
            grow = ~renew & infected
        else:
            renew = (new_life < 0) | (new_life < life)
            grow = (new_life > life) & infected
        got = life_and_rate(life, fitvirus, 0.01, rate, 0.1, 0.1, 1.0, infected, kubota_rule)
        for x, y in zip(got, (new_life, new_rate, np.flatnonzero(renew), np.flatnonzero(grow))):
            assert np.array_equal(x, y)
