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


def former_single_point(A, B, rate, rng):
    """Single-point crossover as it was written before the draws were split off (reference)."""
    m, L = A.shape
    cut = rng.integers(1, L, m) if L > 1 else np.full(m, L)
    cross = rng.random(m) < rate
    mask = (np.arange(L) >= cut[:, None]) & cross[:, None]
    return np.where(mask, B, A), np.where(mask, A, B)


def former_two_point(A, B, rate, rng):
    m, L = A.shape
    if L < 3:
        return former_single_point(A, B, rate, rng)
    c = np.sort(np.stack([rng.integers(1, L, m), rng.integers(1, L, m)], axis=1), axis=1)
    c[:, 1] = np.where(c[:, 0] == c[:, 1], L, c[:, 1])
    cross = rng.random(m) < rate
    pos = np.arange(L)
    mask = (pos >= c[:, :1]) & (pos < c[:, 1:]) & cross[:, None]
    return np.where(mask, B, A), np.where(mask, A, B)


def former_single_point_mutation(G, rate, rng):
    n, L = G.shape
    out = G.copy()
    hit = np.flatnonzero(rng.random(n) < rate)
    out[hit, rng.integers(0, L, n)[hit]] ^= True
    return out


@pytest.mark.parametrize("L", [1, 2, 3, 23, 46])
def test_drawn_operators_give_the_former_operators_children_and_stream(L):
    """Drawing segments and loci, then applying them, takes the generator's numbers in the
    former operators' order and gives their children."""
    for seed in range(10):
        G = np.random.default_rng(seed).random((40, L)) < 0.5
        A, B = G[:20], G[20:]
        for rate in (0.0, 0.8, 1.0):
            for former, segments in ((former_single_point, crossover.single_point_segments),
                                     (former_two_point, crossover.two_point_segments)):
                old_rng, rng = np.random.default_rng(seed), np.random.default_rng(seed)
                expected = former(A, B, rate, old_rng)
                drawn = crossover.swap_segments(A, B, *segments(20, L, rate, rng))
                assert all(np.array_equal(x, y) for x, y in zip(expected, drawn))
                assert old_rng.random() == rng.random()  # the same numbers drawn
            old_rng, rng = np.random.default_rng(seed), np.random.default_rng(seed)
            expected = former_single_point_mutation(G, rate, old_rng)
            loci = mutation.single_point_loci(40, L, rate, rng)
            assert np.array_equal(mutation.flip(G, loci), expected)
            assert old_rng.random() == rng.random()
            assert ((mutation.flip(G, loci) != G).sum(axis=1) == (loci >= 0)).all()
        lo, hi = crossover.single_point_segments(20, L, 0.0, np.random.default_rng(seed))
        assert (lo == L).all()  # a pair that does not cross swaps nothing


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


@pytest.mark.parametrize("n, L, n_children", [(200, 46, 199), (31, 8, 30), (2, 2, 1), (2000, 46, 1999), (40, 10, 37)])
def test_one_pass_breeding_equals_the_operators_one_by_one(n, L, n_children):
    """Rank Eq. 10 -> roulette -> single-point crossover -> single-point mutation, compiled in
    one pass: the operators' children and the generator's numbers, bit for bit, on values with
    ties (clones) and of all signs."""
    from evoplan.operators import selection

    for seed in range(10):
        rng = np.random.default_rng(seed)
        G = rng.random((n, L)) < 0.5
        f = np.round(rng.normal(size=n) * 10.0 ** rng.integers(-3, 4), 1)  # ties
        order = np.argsort(f, kind="stable")
        m = (n_children + 1) // 2

        def one_by_one(r):
            parents = selection.roulette(fitness.exponential_fitness(f, "rank", 2.0, order), 2 * m, r)
            lo, hi = crossover.single_point_segments(m, L, 0.9, r)
            loci = mutation.single_point_loci(n_children, L, 0.5, r)
            return breeding.breed(G, parents[:m], parents[m:], lo, hi, loci, n_children)

        r1, r2 = np.random.default_rng(seed), np.random.default_rng(seed)
        with compiled.forced("never"):
            expected = one_by_one(r1)
        r3, elite = np.random.default_rng(seed), order[:3]
        with compiled.forced("always"):
            got = breeding.breed_ranked_single_point(G, f, order, 2.0, 0.9, 0.5, n_children, r2)
            # the next population in one array: the elite's rows, then the same children
            whole = breeding.breed_ranked_single_point(G, f, order, 2.0, 0.9, 0.5, n_children, r3, elite)
        assert got.dtype == bool and np.array_equal(got, expected)
        assert r1.bit_generator.state == r2.bit_generator.state
        assert np.array_equal(whole, np.concatenate([G[elite], expected]))


def test_one_pass_breeding_steps_aside_without_drawing():
    """The numpy form, a single locus or a sum of values that could overflow: ``None`` and the
    generator untouched (the GA then runs the operators one by one)."""
    G = np.random.default_rng(0).random((10, 5)) < 0.5
    f = np.arange(10.0)
    order = np.argsort(f, kind="stable")
    rng = np.random.default_rng(1)
    state = rng.bit_generator.state
    with compiled.forced("never"):
        assert breeding.breed_ranked_single_point(G, f, order, 2.0, 0.9, 0.5, 9, rng) is None
    with compiled.forced("always"):
        assert breeding.breed_ranked_single_point(G[:, :1], f, order, 2.0, 0.9, 0.5, 9, rng) is None
        assert breeding.breed_ranked_single_point(G, f * 1e299, order, 2.0, 0.9, 0.5, 9, rng) is None
    assert rng.bit_generator.state == state


@pytest.mark.parametrize("N", [1, 2, 7, 200, 2000])
def test_compiled_wheel_equals_the_binary_search(N):
    """The guide-table wheel picks what ``searchsorted(side="right")`` picks, draws that fall
    exactly on a boundary and runs of zero fitness (equal cumulative values) included."""
    from evoplan.operators.selection_kernels import wheel_indices

    rng = np.random.default_rng(N)
    for kind in range(4):
        fit = [rng.random(N), np.where((rng.random(N) < 0.5) & (np.arange(N) > 0), 0.0, rng.random(N)),
               np.exp(-rng.random(N) * 40), np.round(rng.random(N), 1) + (np.arange(N) == 0)][kind]
        cum = np.cumsum(fit)
        u = np.concatenate([rng.random(3000), [0.0, np.nextafter(1.0, 0.0)], cum[:-1] / cum[-1]])
        u = np.minimum(u, np.nextafter(1.0, 0.0))
        expected = np.minimum(np.searchsorted(cum, u * cum[-1], side="right"), N - 1)
        assert np.array_equal(wheel_indices(cum, u), expected)
