"""VEGA's infection round compiled (numba): reverse transcription with its "changed" flags
(:func:`transcribe`) and the round's outcome (:func:`infection_outcome`).

:mod:`evoplan.operators.viral_outcome` calls these once they pay (:mod:`evoplan.compiled`),
and its numpy matrix form otherwise: the same numbers, bit for bit. The outcome is computed
from the infection pairs in one loop instead of (virus x host) matrices, ``argmin`` /
``argmax`` and ``bincount`` (the pairs come sorted by virus, then host, as ``np.nonzero``
gives them, so "first" means the same), without a dozen small-array numpy calls per
generation.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True)
def transcribe(trials, virus, start, length, bits):
    """Overwrite the loci ``[start, start + length)`` of virus ``virus[p]`` in row ``p`` of
    ``trials`` by its ``bits``, in place; whether a bit changed, per row."""
    changed = np.zeros(trials.shape[0], dtype=np.bool_)
    for p in range(trials.shape[0]):
        v = virus[p]
        ch = False
        for k in range(start[v], start[v] + length[v]):  # no branch: a vector loop
            b = bits[v, k]
            ch |= trials[p, k] != b
            trials[p, k] = b
        changed[p] = ch
    return changed


@numba.njit(cache=True)
def infection_outcome(virus, host, changed, f_trial, f_host, n_viruses, improve):
    """One infection round's outcome.

    ``virus, host: (P,)`` the pairs (sorted by virus, then host); ``changed: (P,)`` whether
    the trial differs from its host; ``f_trial: (P,)`` each trial's value (the host's where
    unchanged); ``f_host: (N,)`` the hosts' values; ``improve``: replace only by a better trial.

    Returns ``(take, best, best_f, fitvirus, infected, best_pair)``: ``take: (N,)`` the hosts
    replaced by their best trial ``best: (N,)`` (a pair index) of value ``best_f: (N,)`` (the
    first lowest value over the viruses; a failed (non-finite) best never replaces);
    ``fitvirus: (V,)`` Fountas Eq. 12, the sum of the Eq. 11 gains ``f(host) - f(trial)``
    (0 for an unchanged trial or a non-finite gain); ``infected: (V,)``; ``best_pair: (V,)``
    the pair of each virus with the largest gain (the first such host; -1 if none).
    """
    P, N = virus.size, f_host.size
    best = np.full(N, -1, dtype=np.int64)
    best_f = np.full(N, np.inf)
    poisoned = np.zeros(N, dtype=np.bool_)  # a NaN value: numpy's argmin would pick it
    fitvirus = np.zeros(n_viruses)
    infected = np.zeros(n_viruses, dtype=np.bool_)
    best_pair = np.full(n_viruses, -1, dtype=np.int64)
    best_gain = np.full(n_viruses, -np.inf)
    for p in range(P):
        v, j, f = virus[p], host[p], f_trial[p]
        if np.isnan(f):
            poisoned[j] = True
        elif f < best_f[j]:
            best_f[j], best[j] = f, p
        gain = 0.0
        if changed[p]:
            gain = f_host[j] - f
            if not np.isfinite(gain):
                gain = 0.0
        fitvirus[v] += gain
        infected[v] = True
        if gain > best_gain[v]:
            best_gain[v], best_pair[v] = gain, p
    take = np.zeros(N, dtype=np.bool_)
    for j in range(N):
        take[j] = best[j] >= 0 and not poisoned[j] and np.isfinite(best_f[j])
        if improve and take[j]:
            take[j] = best_f[j] < f_host[j]
    return take, best, best_f, fitvirus, infected, best_pair


@numba.njit(cache=True)
def substrings(hosts, start, length):
    """``hosts`` kept on the loci ``[start[i], start[i] + length[i])`` of each row, zero
    elsewhere: :func:`evoplan.operators.viral.transduction`'s bits."""
    V, L = hosts.shape
    out = np.zeros((V, L), dtype=np.bool_)
    for i in range(V):
        for j in range(start[i], start[i] + length[i]):
            out[i, j] = hosts[i, j]
    return out


@numba.njit(cache=True)
def partial_transduction(start, length, bits, hosts, cap, growth, right):
    """:func:`evoplan.operators.viral.partial_transduction` after its draw ``right: (V,)``
    (the side each window grows to): the same windows and bits, one row at a time."""
    V, L = hosts.shape
    new_start = np.empty(V, dtype=np.int64)
    new_len = np.empty(V, dtype=np.int64)
    out = np.zeros((V, L), dtype=np.bool_)
    for i in range(V):
        n = max(min(length[i] + growth, cap), length[i])
        s = start[i] + (length[i] + growth - n) if right[i] else start[i] - growth
        s = min(max(s, 0), L - n)
        new_start[i], new_len[i] = s, n
        old_lo, old_hi = start[i], start[i] + length[i]
        for j in range(s, s + n):
            out[i, j] = bits[i, j] if old_lo <= j < old_hi else hosts[i, j]
    return new_start, new_len, out


@numba.njit(cache=True)
def pairs_below(u, rate):
    """``np.nonzero(u < rate[:, None])`` for ``u: (V, N)``: the ``(virus, host)`` pairs whose
    draw falls under the virus' infection rate, sorted by virus, then host, in one pass."""
    V, N = u.shape
    virus = np.empty(V * N, dtype=np.int64)
    host = np.empty(V * N, dtype=np.int64)
    p = 0
    for i in range(V):
        r = rate[i]
        for j in range(N):
            if u[i, j] < r:
                virus[p], host[p] = i, j
                p += 1
    return virus[:p].copy(), host[:p].copy()


@numba.njit(cache=True)
def life_and_rate(life, fitvirus, reduction, rate, step, low, high, infected, kubota_rule):
    """Rules 4-6's bookkeeping in one pass: Kubota's life force
    (:func:`evoplan.operators.viral.update_life`), the adapted infection rate
    (:func:`~evoplan.operators.viral.adapt_infection_rate`) and the viruses to renew and to
    grow, as :meth:`evoplan.algorithms.vega.VEGA.update_viruses` decides them; the same numbers.

    Returns ``(life, rate, renew, grow)``, the last two as ascending indices."""
    V = life.size
    new_life = np.empty(V)
    new_rate = np.empty(V)
    renew = np.empty(V, dtype=np.int64)
    grow = np.empty(V, dtype=np.int64)
    n_renew = n_grow = 0
    up, down = 1.0 + step, 1.0 - step
    for i in range(V):
        x = reduction * life[i] + fitvirus[i]
        new_life[i] = x
        r = rate[i] * (up if fitvirus[i] > 0 else (down if fitvirus[i] < 0 else 1.0))
        if r < low:
            r = low
        if r > high:
            r = high
        new_rate[i] = r
        if kubota_rule:
            renewed = x < 0
            grows = not renewed and infected[i]
        else:
            renewed = x < 0 or x < life[i]
            grows = x > life[i] and infected[i]
        if renewed:
            renew[n_renew] = i
            n_renew += 1
        if grows:
            grow[n_grow] = i
            n_grow += 1
    return new_life, new_rate, renew[:n_renew].copy(), grow[:n_grow].copy()
