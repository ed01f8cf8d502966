"""Zoning method ``amas``: Djebali's Adaptive Multi-Agent System (Sec. 5; the model and
its two readings of the satisfaction are documented in ``zoning/amas.py``)."""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field, field_validator

from ....checks import interval
from ..amas import amas_zoning
from .base import Gene, ZoningMethod, ZoningSettings

__all__ = ["Amas"]


class AmasSettings(ZoningSettings):
    k_cmd: float = Field(1.0, description="weight of the Closest Machining Directions criterion")
    k_lz: float = Field(0.15, description="weight of the Largest Zone criterion (Djebali: "
                                          "0.15 for Delta L = 40 mm, 0.35 for 300 mm)")
    satisfaction: Literal["weighted", "printed"] = Field(
        "weighted", description="zone score: worst weighted dissatisfaction, or the printed min")
    neutral_slope_deg: float = Field(
        0.0, ge=0, le=90, description="cells flatter than this do not count in a zone's sector")
    max_cycles: int = Field(1000, ge=1, description="cycles before the run stops unsettled")

    @field_validator("k_cmd", "k_lz")
    @classmethod
    def _unit(cls, v: float) -> float:
        if not 0.0 <= v <= 1.0:
            raise ValueError(f"must be in [0, 1], got {v!r}")
        return v


class Amas(ZoningMethod):
    """Djebali's multi-agent system: cells move between zones to balance CMD and LZ."""

    name = "amas"
    Settings = AmasSettings
    gene = Gene("k_lz", "k_lz", integer=False, bounds=(0.02, 0.6))

    def gene_range(self, value, features):
        lo, hi = interval(value, "k_lz")
        if lo < 0 or hi > 1:
            raise ValueError(f"k_lz: the range must lie in [0, 1], got {list(value)!r}")
        return lo, hi

    def labels(self, features, settings, seed=0):
        neutral = features.slope < np.radians(settings.neutral_slope_deg)
        res = amas_zoning(features.optimal_feed, k_cmd=settings.k_cmd, k_lz=settings.k_lz,
                          seed=seed, satisfaction=settings.satisfaction, neutral=neutral,
                          max_cycles=settings.max_cycles)
        return res.labels, {"cycles": res.cycles, "actions": res.actions,
                            "settled": res.settled, "k_cmd": settings.k_cmd,
                            "k_lz": settings.k_lz}
