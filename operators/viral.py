"""Viral operators of the virus-evolutionary GA (Kubota et al. 1996; Fountas et al., Fig. 3).

A population of ``V`` viruses over hosts of ``L`` bits is three arrays:
``start: (V,) int``, ``length: (V,) int`` (a virus is the contiguous loci
``[start, start + length)`` of a host chromosome) and ``bits: (V, L) bool`` (the virus' values,
meaningful on its loci only, zero elsewhere). Every function is vectorized over rows: row ``i``
of the host arrays goes with virus ``i``.
"""

from __future__ import annotations

import numpy as np

from ..compiled import use_compiled


def loci_mask(start: np.ndarray, length: np.ndarray, L: int) -> np.ndarray:
    """``(V, L) bool``: True on each virus' loci ``[start, start + length)``."""
    pos = np.arange(L)
    return (pos >= start[:, None]) & (pos < (start + length)[:, None])


def transduction(
    hosts: np.ndarray, max_length: int, rng: np.random.Generator, min_length: int = 1
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Transduction, Fig. 3a: each virus copies a random substring of its host.

    ``hosts: (V, L)`` (one host per new virus). The length is uniform on
    ``[min_length, min(max_length, L)]``, the start uniform among the positions that keep the
    substring inside the host (Fountas: both loci "constrained to the host's chromosome length").
    Returns ``(start, length, bits)`` (the bits by :mod:`.viral_kernels` once it pays: the same).
    """
    V, L = hosts.shape
    hi = max(1, min(int(max_length), L))
    lo = max(1, min(int(min_length), hi))
    length = rng.integers(lo, hi + 1, V)
    start = (rng.random(V) * (L - length + 1)).astype(np.int64)
    if hosts.dtype == bool and use_compiled():
        from .viral_kernels import substrings  # numba: imported only when it pays

        return start, length, substrings(hosts, start, length)
    bits = hosts & loci_mask(start, length, L)
    return start, length, bits


def reverse_transcription(
    hosts: np.ndarray, start: np.ndarray, length: np.ndarray, bits: np.ndarray
) -> np.ndarray:
    """Reverse transcription (infection), Fig. 3b: the virus overwrites its loci in the host.

    ``hosts: (P, L)``; ``start, length: (P,)``; ``bits: (P, L)`` -> infected hosts ``(P, L)``.
    Bits outside the virus' loci are the host's, unchanged.
    """
    return np.where(loci_mask(start, length, hosts.shape[1]), bits, hosts)


def infect(
    G: np.ndarray, host: np.ndarray, virus: np.ndarray,
    start: np.ndarray, length: np.ndarray, bits: np.ndarray,
) -> np.ndarray:
    """Reverse transcription of many ``(virus, host)`` pairs at once: ``(P, L)`` infected hosts.

    Row ``p`` is host ``G[host[p]]`` with the loci of virus ``virus[p]`` overwritten by its bits,
    exactly :func:`reverse_transcription`; ``virus`` must be sorted (as ``np.nonzero`` of a
    virus-by-host matrix gives it), so that each virus writes one rectangular block.
    """
    out = np.take(G, host, axis=0)  # G[host], 4x faster at 2000 pairs
    bounds = np.searchsorted(virus, np.arange(start.size + 1))
    for v in np.flatnonzero(bounds[1:] > bounds[:-1]):
        s, e = start[v], start[v] + length[v]
        out[bounds[v] : bounds[v + 1], s:e] = bits[v, s:e]
    return out


def partial_transduction(
    start: np.ndarray,
    length: np.ndarray,
    bits: np.ndarray,
    hosts: np.ndarray,
    max_length: int,
    rng: np.random.Generator,
    growth: int = 1,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Partial transduction, Fig. 3c: a successful virus takes a partially new substring.

    The loci window grows by ``growth`` loci on a randomly chosen side (the other side where
    the host ends), taking the new loci's bits from ``hosts: (V, L)`` (the host each virus
    infected) and keeping its own bits elsewhere. A virus already at ``max_length`` (Fountas'
    ``VrsLgth`` limit) slides its window by ``growth`` instead: it drops loci at one end and
    takes as many new ones from the host at the other, renewing part of itself.
    Returns the new ``(start, length, bits)``; the compiled form (:mod:`.viral_kernels`, once
    it pays) gives the same.
    """
    V, L = hosts.shape
    cap = min(int(max_length), L)
    if hosts.dtype == bool and bits.dtype == bool and use_compiled():
        from . import viral_kernels  # numba: imported only when it pays

        return viral_kernels.partial_transduction(start.astype(np.int64), length.astype(np.int64), bits,
                                                  hosts, cap, int(growth), rng.random(V) < 0.5)
    new_len = np.minimum(length + growth, cap)
    new_len = np.maximum(new_len, length)  # never shrink a virus that is already longer
    right = rng.random(V) < 0.5
    # grow to the right: keep start; to the left: move start back. Clip into the host.
    new_start = np.where(right, start + (length + growth - new_len), start - growth)
    new_start = np.minimum(np.maximum(new_start, 0), L - new_len)  # (np.clip's numbers, without its wrapper)
    old = loci_mask(start, length, L)
    new = loci_mask(new_start, new_len, L)
    new_bits = np.where(old & new, bits, hosts) & new
    return new_start, new_len, new_bits


def virus_fitness(gain: np.ndarray, virus: np.ndarray, n_viruses: int) -> np.ndarray:
    """Fountas Eq. 12: ``fitvirus_i = sum_j fitvirus_ij`` over the hosts virus ``i`` infected.

    ``gain: (P,)`` the Eq. 11 improvement of each infection (positive = the host got better),
    ``virus: (P,)`` the index of the virus of each infection. Returns ``(n_viruses,)``.
    """
    return np.bincount(virus, weights=gain, minlength=n_viruses)


def infection_gain(f_before: np.ndarray, f_after: np.ndarray) -> np.ndarray:
    """Fountas Eq. 11 for a minimized objective: ``fitvirus_ij = f(host) - f(infected host)``.

    Eq. 11 is written for a fitness to maximize (after minus before); with an objective to
    minimize the improvement is before minus after. Where either value is non-finite (a failed
    evaluation) the gain is 0: one crash neither kills a virus nor makes it immortal.
    """
    with np.errstate(invalid="ignore"):
        gain = f_before - f_after
    return np.where(np.isfinite(gain), gain, 0.0)


def update_life(life: np.ndarray, fitvirus: np.ndarray, reduction: float) -> np.ndarray:
    """Kubota's life force: ``life_i(t+1) = r * life_i(t) + fitvirus_i(t)``."""
    return reduction * life + fitvirus


def adapt_infection_rate(
    rate: np.ndarray, fitvirus: np.ndarray, step: float, low: float, high: float
) -> np.ndarray:
    """Kubota's self-adaptive infection rate, bounded as Fountas does.

    ``rate_i *= 1 + step`` after a gain (``fitvirus_i > 0``), ``1 - step`` after a loss, unchanged
    otherwise; then clipped to ``[MinInfRate, MaxInfRate] = [low, high]``.
    """
    factor = np.where(fitvirus > 0, 1.0 + step, np.where(fitvirus < 0, 1.0 - step, 1.0))
    return np.minimum(np.maximum(rate * factor, low), high)  # (np.clip's numbers, without its wrapper)
