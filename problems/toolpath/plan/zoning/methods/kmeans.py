"""Zoning method ``kmeans``: Herraz's K-means on (u, v, s, theta), split into connected
zones (Herraz Sec. 2.1-2.3; the algorithm is in ``zoning/kmeans.py``)."""

from __future__ import annotations

from typing import Annotated

from pydantic import AliasChoices, Field

from ..kmeans import kmeans_zoning
from .base import Gene, ZoningMethod, ZoningSettings

__all__ = ["KMeans"]


class KMeansSettings(ZoningSettings):
    K: int = Field(3, ge=1, validation_alias=AliasChoices("K", "k"),
                   description="clusters (Herraz's K); disconnected clusters give more zones")
    weights: list[Annotated[float, Field(ge=0)]] = Field(
        default_factory=lambda: [1.0, 1.0, 1.0, 1.0], min_length=4, max_length=4,
        description="weights of the (u, v, slope, direction) features")


class KMeans(ZoningMethod):
    """Herraz's K-means clusters on (u, v, slope, direction), split into connected zones."""

    name = "kmeans"
    Settings = KMeansSettings
    gene = Gene("zones", "K", integer=True, bounds=(1, 8))

    def gene_range(self, value, features):
        lo, hi = super().gene_range(value, features)
        if lo < 1 or hi > features.size:
            raise ValueError(f"zones: expected integers in [1, {features.size}] "
                             f"(the mesh's cells), got {list(value)!r}")
        return lo, hi

    def labels(self, features, settings, seed=0):
        return kmeans_zoning(features, settings.K, tuple(settings.weights)), {"K": settings.K}
