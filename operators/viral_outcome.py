"""One infection round of the virus-evolutionary GA: the infected hosts (:func:`infect_pairs`)
and the round's outcome (:func:`infection_outcome`).

After the infected hosts are evaluated, VEGA needs, per host, its best infected version
(rule 3, replacement) and, per virus, its Eq. 12 fitness, whether it infected anyone and the
infection that improved its host most (rules 4-6). Both functions have two forms with the
same numbers, bit for bit: numpy (reverse transcription by :func:`viral.infect`, then the
outcome from (virus x host) matrices) and compiled (:mod:`evoplan.operators.viral_kernels`,
one loop over the pairs). The compiled form is taken once it pays for loading numba
(:func:`evoplan.compiled.use_compiled`).
"""

from __future__ import annotations

import numpy as np

from ..compiled import use_compiled
from . import viral

__all__ = ["infect_pairs", "infection_outcome", "outcome_matrices"]


def infect_pairs(G, host, virus, start, length, bits):
    """Reverse transcription (Fig. 3b) of the ``(virus, host)`` pairs: ``(trials, changed)``.

    ``trials: (P, L)`` row ``p`` is host ``G[host[p]]`` with the loci ``[start, start +
    length)`` of virus ``virus[p]`` overwritten by its ``bits``, exactly
    :func:`evoplan.operators.viral.infect`; ``changed: (P,)`` whether that altered a bit.
    """
    if use_compiled(virus.size):
        from .viral_kernels import transcribe

        trials = np.take(G, host, axis=0)  # a copy; 4x faster than G[host] at 2000 pairs
        return trials, transcribe(trials, virus, start, length, bits)
    trials = viral.infect(G, host, virus, start, length, bits)
    return trials, (trials != np.take(G, host, axis=0)).any(axis=1)


def infection_outcome(virus, host, changed, f_trial, f_host, n_viruses, improve):
    """One infection round's outcome.

    ``virus, host: (P,)`` the pairs (sorted by virus, then host, as ``np.nonzero`` gives
    them); ``changed: (P,)`` whether the trial differs from its host; ``f_trial: (P,)`` each
    trial's value (the host's where unchanged); ``f_host: (N,)`` the hosts' values;
    ``improve``: replace only by a better trial.

    Returns ``(take, best, best_f, fitvirus, infected, best_pair)``: ``take: (N,)`` the hosts
    replaced by their best trial ``best: (N,)`` (a pair index) of value ``best_f: (N,)`` (the
    first lowest value over the viruses; a failed (non-finite) best never replaces; ``best``
    and ``best_f`` are meant only where ``take``); ``fitvirus: (V,)`` Fountas Eq. 12, the sum
    of the Eq. 11 gains ``f(host) - f(trial)`` (0 for an unchanged trial or a non-finite
    gain); ``infected: (V,)``; ``best_pair: (V,)`` the pair of each virus with the largest
    gain (the first such host; -1 if none).
    """
    if use_compiled():
        from .viral_kernels import infection_outcome as compiled

        return compiled(virus, host, changed, f_trial, f_host, n_viruses, improve)
    return outcome_matrices(virus, host, changed, f_trial, f_host, n_viruses, improve)


def outcome_matrices(virus, host, changed, f_trial, f_host, n_viruses, improve):
    """:func:`infection_outcome` in numpy: rule 3 as an ``argmin`` over the viruses of a
    (virus x host) matrix of values, Eq. 11-12 as a ``bincount`` of the gains, each virus's
    best infection as an ``argmax`` over its hosts."""
    V, N = n_viruses, f_host.size
    trial = np.full((V, N), -1)
    trial[virus, host] = np.arange(virus.size)
    F = np.full((V, N), np.inf)
    F[virus, host] = f_trial
    gain = np.where(changed, viral.infection_gain(f_host[host], f_trial), 0.0)
    best_virus = F.argmin(axis=0)  # a NaN value is picked first, and then never taken
    cols = np.arange(N)
    best, best_f = trial[best_virus, cols], F[best_virus, cols]
    take = (best >= 0) & np.isfinite(best_f)
    if improve:
        take &= best_f < f_host
    G = np.full((V, N), -np.inf)
    G[virus, host] = gain
    infected = (trial >= 0).any(axis=1)
    best_pair = np.where(infected, trial[np.arange(V), G.argmax(axis=1)], -1)
    return take, best, best_f, viral.virus_fitness(gain, virus, V), infected, best_pair
