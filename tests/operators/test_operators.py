import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from evoplan.operators import crossover, elitism, fitness, mutation, selection

pairs = st.integers(1, 12).flatmap(
    lambda m: st.integers(2, 50).flatmap(
        lambda L: st.tuples(arrays(bool, (m, L)), arrays(bool, (m, L)), st.integers(0, 2**32 - 1))
    )
)


@settings(max_examples=80, deadline=None)
@given(pairs, st.sampled_from([crossover.single_point, crossover.two_point]))
def test_crossover_keeps_lengths_and_takes_each_locus_from_a_parent(case, op):
    A, B, seed = case
    c1, c2 = op(A, B, 1.0, np.random.default_rng(seed))
    assert c1.shape == A.shape and c2.shape == B.shape and c1.dtype == bool
    # every locus comes from one parent, the other child gets the other parent's bit
    assert ((c1 == A) | (c1 == B)).all()
    assert np.array_equal(c1 ^ c2, A ^ B)
    swapped = (c1 != A) & (A != B)
    # the swapped loci form one segment: a tail (single point) or an inner segment (two point)
    for row, a, b, c in zip(swapped, A, B, c1):
        taken = np.flatnonzero(c != a)
        if taken.size:
            from_b = (c == b)
            lo, hi = taken.min(), taken.max()
            assert from_b[lo : hi + 1].all()
            if op is crossover.single_point:
                assert from_b[lo:].all()


def test_crossover_rate_zero_copies_parents():
    rng = np.random.default_rng(0)
    A, B = rng.random((10, 30)) < 0.5, rng.random((10, 30)) < 0.5
    c1, c2 = crossover.single_point(A, B, 0.0, rng)
    assert np.array_equal(c1, A) and np.array_equal(c2, B)


@settings(max_examples=60, deadline=None)
@given(arrays(bool, st.tuples(st.integers(1, 30), st.integers(1, 60))), st.integers(0, 2**32 - 1))
def test_single_point_mutation_flips_at_most_one_bit(G, seed):
    out = mutation.single_point(G, 1.0, np.random.default_rng(seed))
    assert out.shape == G.shape and out.dtype == bool
    assert ((out != G).sum(axis=1) == 1).all()
    assert np.array_equal(mutation.single_point(G, 0.0, np.random.default_rng(seed)), G)


def test_per_bit_mutation_rate():
    rng = np.random.default_rng(1)
    G = np.zeros((400, 50), bool)
    assert np.array_equal(mutation.per_bit(G, 1.0, rng), ~G)
    flipped = mutation.per_bit(G, 0.05, rng).mean()
    assert 0.04 < flipped < 0.06
    assert not G.any()  # the input is not modified


def test_roulette_follows_fitness():
    rng = np.random.default_rng(2)
    fit = np.array([0.0, 1.0, 3.0, 0.0])
    idx = selection.roulette(fit, 40000, rng)
    counts = np.bincount(idx, minlength=4) / idx.size
    assert counts[0] == 0 and counts[3] == 0
    assert counts[2] == pytest.approx(0.75, abs=0.01)


def test_tournament_picks_the_best_contestant():
    rng = np.random.default_rng(3)
    fit = np.arange(10.0)
    assert (selection.tournament(fit, 200, rng, size=200) == 9).mean() > 0.99
    winners = selection.tournament(fit, 5000, rng, size=2)
    assert winners.mean() > 5.5  # better than uniform (4.5)


def test_elitism_returns_the_lowest_objectives():
    f = np.array([3.0, np.nan, -1.0, 2.0, np.inf])
    assert elite_list(f, 2) == [2, 3]
    assert elite_list(f, 0) == []


def elite_list(f, k):
    return elitism.elite_indices(f, k).tolist()


@pytest.mark.parametrize("method", ["rank", "minmax"])
def test_exponential_fitness_eq10_orders_like_the_objective(method):
    f = np.array([5.0, 0.1, 2.0, np.inf, 1.0])
    fit = fitness.exponential_fitness(f, method, pressure=1.0)
    assert (fit > 0).all()
    assert np.argmax(fit) == 1 and fit[3] == fit.min()  # a failure ranks last (minmax: tied with the worst)
    assert np.all(np.diff(fit[np.argsort(f)]) <= 0)
    v = fitness.normalize(f, method)
    # Eq. 10 exactly: FitSum * exp(-ObjVal^2), FitSum the sum of the (finite) objective values
    np.testing.assert_allclose(fit, 8.1 * np.exp(-(v**2)))


def test_rank_normalization_is_scale_free():
    f = np.array([3.0, 1.0, 2.0])
    np.testing.assert_allclose(fitness.normalize(f), [1.0, 0.0, 0.5])
    np.testing.assert_allclose(fitness.normalize(f * 1e9 + 7), fitness.normalize(f))
