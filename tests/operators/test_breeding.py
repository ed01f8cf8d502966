"""The compiled breeding pass against the numpy operators it replaces: the same children."""

import numpy as np
import pytest

from evoplan import compiled
from evoplan.operators import breeding, crossover, fitness, mutation
from evoplan.operators.breeding_kernels import breed_pairs


@pytest.mark.parametrize("segments", [crossover.single_point_segments, crossover.two_point_segments])
@pytest.mark.parametrize("n, L, n_children", [(30, 46, 29), (31, 8, 31), (7, 2, 6), (200, 46, 199), (5, 1, 4)])
def test_compiled_children_equal_the_numpy_operators(segments, n, L, n_children):
    for seed in range(20):
        rng = np.random.default_rng(seed)
        G = rng.random((n, L)) < 0.5
        m = (n_children + 1) // 2
        parents = rng.integers(0, n, 2 * m)
        lo, hi = segments(m, L, 0.7, rng)
        loci = mutation.single_point_loci(n_children, L, 0.5, rng)
        A, B = crossover.swap_segments(G[parents[:m]], G[parents[m:]], lo, hi)
        expected = mutation.flip(np.concatenate([A, B])[:n_children], loci)
        got = breed_pairs(G, parents[:m], parents[m:], lo, hi, loci, n_children)
        assert got.dtype == bool and np.array_equal(got, expected)
        previous = compiled.set_mode("never")
        try:
            assert np.array_equal(breeding.breed(G, parents[:m], parents[m:], lo, hi, loci, n_children), expected)
        finally:
            compiled.set_mode(previous)


def test_drawn_operators_give_the_children_of_the_whole_operators():
    """Drawing segments and loci, then applying them, is the operators' own stream and result."""
    G = np.random.default_rng(0).random((40, 23)) < 0.5
    A, B = G[:20], G[20:]
    for op, segments in ((crossover.single_point, crossover.single_point_segments),
                         (crossover.two_point, crossover.two_point_segments)):
        whole = op(A, B, 0.8, np.random.default_rng(3))
        rng = np.random.default_rng(3)
        drawn = crossover.swap_segments(A, B, *segments(20, 23, 0.8, rng))
        assert all(np.array_equal(x, y) for x, y in zip(whole, drawn))
        # a pair that does not cross swaps nothing
        lo, hi = segments(20, 23, 0.0, np.random.default_rng(3))
        assert (lo == 23).all()
    loci = mutation.single_point_loci(40, 23, 0.5, np.random.default_rng(4))
    assert np.array_equal(mutation.single_point(G, 0.5, np.random.default_rng(4)), mutation.flip(G, loci))
    assert ((mutation.flip(G, loci) != G).sum(axis=1) == (loci >= 0)).all()


@pytest.mark.parametrize("n", [2, 3, 200, 2001])
def test_rank_factors_give_eq10_as_computed_from_the_ranks(n):
    rng = np.random.default_rng(n)
    for _ in range(5):
        f = rng.normal(size=n) * 10
        order = np.argsort(f, kind="stable")
        v = fitness.normalize(f, "rank") * 2.0
        expected = np.abs(f).sum() * np.exp(-(v * v))
        assert np.array_equal(fitness.exponential_fitness(f, "rank", 2.0, order), expected)
        assert np.array_equal(fitness.exponential_fitness(f, "rank", 2.0), expected)
    with pytest.raises(ValueError):
        fitness.rank_factors(n, 2.0)[0] = 1.0  # the memoized table is read-only
