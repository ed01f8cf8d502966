"""Checks of plain input data; each error is one line that starts with the key path."""

from __future__ import annotations

import numpy as np


def number(value, key: str, positive: bool = False) -> float:
    """A finite float (``> 0`` when ``positive``) from ``value``; ``ValueError`` naming ``key``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{key}: expected a number, got {value!r}") from None
    if isinstance(value, bool) or not np.isfinite(x):
        raise ValueError(f"{key}: expected a finite number, got {value!r}")
    if positive and not x > 0:
        raise ValueError(f"{key}: must be a finite number > 0, got {value!r}")
    return x


def interval(value, key: str) -> tuple[float, float]:
    """A pair ``[lo, hi]`` of finite floats with ``lo < hi``; ``ValueError`` naming ``key``."""
    try:
        lo, hi = (float(x) for x in value)
    except (TypeError, ValueError):
        raise ValueError(f"{key}: expected [lo, hi], got {value!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
        raise ValueError(f"{key}: expected finite lo < hi, got {value!r}")
    return lo, hi
