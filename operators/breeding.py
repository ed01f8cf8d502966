"""Children from parents: crossover segments and mutation flips applied in one step.

The operators draw (``crossover.*_segments``, ``mutation.single_point_loci`` /
``per_bit_mask``); :func:`breed` applies. Its numpy form gathers the parents, builds the
segment masks, swaps and flips, about fifteen array calls per generation; the compiled form
(:mod:`.breeding_kernels`, once it pays: :func:`evoplan.compiled.use_compiled`) writes each
child once from its two parents. The same children, bit for bit.
"""

from __future__ import annotations

import numpy as np

from ..compiled import use_compiled
from .crossover import swap_segments
from .fitness import rank_factors
from .mutation import flip

# a population whose summed objective values reach this is bred by the operators one by one
# (the compiled pass's cumulative fitness must not overflow)
FITSUM_LIMIT = 1e300


def breed(G: np.ndarray, a: np.ndarray, b: np.ndarray, lo: np.ndarray, hi: np.ndarray,
          flips: np.ndarray, n_children: int) -> np.ndarray:
    """``n_children`` children of the pairs ``(G[a[i]], G[b[i]])``: pair ``i`` swaps the loci
    ``[lo[i], hi[i])``; children ``i`` and ``m + i`` (``m = a.size``) are its two, the first
    ``n_children`` kept; then ``flips`` (``mutation.flip``) is applied."""
    if G.dtype == bool and flips.ndim == 1 and use_compiled(n_children):
        from .breeding_kernels import breed_pairs  # numba: imported only when it pays

        return breed_pairs(G, a, b, lo, hi, flips, n_children)
    A, B = swap_segments(G[a], G[b], lo, hi)
    return flip(np.concatenate([A, B])[:n_children], flips)


def breed_ranked_single_point(G: np.ndarray, f: np.ndarray, order: np.ndarray, pressure: float,
                              crossover_rate: float, mutation_rate: float, n_children: int,
                              rng: np.random.Generator, elite: np.ndarray | None = None) -> np.ndarray | None:
    """``n_children`` children of ``(G, f)`` by the paper's default operators in one compiled
    pass: Eq. 10 on ranks (``order``: the stable sort of ``f``, every value finite), roulette,
    single-point crossover, single-point mutation
    (:func:`.breeding_kernels.breed_ranked_single_point`).

    It draws what ``roulette``, ``single_point_segments`` and ``single_point_loci`` draw, in
    their order, and gives their children bit for bit, after the rows ``G[elite]`` (none by
    default): the next population in one array, with no copy to join them. ``None``, having
    drawn nothing, where that pass does not serve (the numpy form chosen, fewer than two loci,
    a non-finite or huge sum of objective values): the caller then runs the operators one by
    one."""
    N, L = G.shape
    if L < 2 or N < 2 or G.dtype != bool or not use_compiled():  # (rows counted by breed's path)
        return None
    fitsum = float(np.abs(f).sum())
    if not fitsum < FITSUM_LIMIT:
        return None
    from .breeding_kernels import breed_ranked_single_point as kernel

    m = (n_children + 1) // 2
    u_select = rng.random(2 * m)
    cut, u_cross = rng.integers(1, L, m), rng.random(m)
    u_mutate, locus = rng.random(n_children), rng.integers(0, L, n_children)
    return kernel(G, order, rank_factors(N, float(pressure)), fitsum if fitsum > 0 else 1.0, u_select,
                  cut, u_cross, float(crossover_rate), u_mutate, locus, float(mutation_rate), n_children,
                  np.empty(0, dtype=np.int64) if elite is None else np.asarray(elite, dtype=np.int64))
