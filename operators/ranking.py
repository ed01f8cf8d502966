"""The population's order: a stable sort of the objective values, best first.

Eq. 10's ranks, the elite and VEGA's elite pool all come from the stable sort (ties kept in
population order). A stable sort's permutation is unique, so its numpy form and its compiled
form (:mod:`.ranking_kernels`, a radix sort: 33 us against numpy's 78 us for 2000 values on
the 2-core host, but 6.6 us against 3.0 us for 200) give the same order; the compiled one
serves from :data:`COMPILED_FROM` values on, once it pays (:func:`evoplan.compiled.use_compiled`).
"""

from __future__ import annotations

import numpy as np

from ..compiled import use_compiled

COMPILED_FROM = 512


def stable_order(f: np.ndarray, finite: bool = False) -> np.ndarray:
    """``np.argsort(f, kind="stable")`` of ``f: (n,)`` with NaN ranked as ``inf`` (last, in
    population order among the failures); ``finite``: the caller knows every value is."""
    f = np.asarray(f, dtype=float)
    if f.size >= COMPILED_FROM and use_compiled():
        from .ranking_kernels import radix_order  # numba: imported only when it pays

        return radix_order(f)
    if not finite and np.isnan(f).any():
        f = np.where(np.isnan(f), np.inf, f)
    return np.argsort(f, kind="stable")
