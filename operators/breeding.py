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
from .mutation import flip


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
