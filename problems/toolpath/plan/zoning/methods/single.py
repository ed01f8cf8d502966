"""Zoning method ``single``: the whole surface as one zone (Djebali Sec. 6.1's
"straightforward" plan, machined along one optimized direction)."""

from __future__ import annotations

import numpy as np

from .base import ZoningMethod, ZoningSettings

__all__ = ["Single"]


class Single(ZoningMethod):
    """One zone: the whole surface."""

    name = "single"
    Settings = ZoningSettings

    def labels(self, features, settings, seed=0):
        return np.zeros(features.shape, np.int64), {}
