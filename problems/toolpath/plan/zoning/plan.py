"""A machining plan by zones: zoning, then per-zone direction, then Djebali Eq. 4.

    total = sum over zones of Lg(z, alpha_opt(z)) + (|Z| - 1) * Delta L     (Djebali Eq. 4)

Zoning methods come from the registry of ``methods/``: ``single`` (one zone: the
"straightforward" plan of Djebali Sec. 6.1), ``kmeans`` (Herraz's C4DO1D: ``kmeans.py``) and
``amas`` (Djebali's multi-agent system: ``amas.py``); any method's zones are then merged as
``merge.py`` explains (a minimum zone area, then Eq. 4 merging; ``merge=None``: none). Each
zone's direction is optimized on its own (``direction.py``) and its passes laid out by
``passes.py`` on the dense samples of ``samples.py``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from pydantic import ValidationError

from ...checks import number
from ...geometry.surface import Surface
from .direction import axial_mean, optimize_direction
from .features import MeshFeatures, check_mesh, mesh_features
from .merge import MergeSettings, merge_zones
from .methods import get_method, method_names
from .methods.base import one_line
from .passes import ZonePasses, length_lower_bound
from .samples import SurfaceSamples, sample_surface
from .stepover import ScallopTarget

__all__ = ["METHODS", "ZonePlan", "ZoningPlan", "zone_labels", "plan_zones", "plan_from_labels"]

METHODS = method_names()  # the built-in methods; the registry (methods/) is the reference


@dataclass(frozen=True)
class ZonePlan:
    """One zone: its cells, area (mm^2), start and best direction (deg), passes, bound."""

    zone: int
    cells: int
    area: float
    start_deg: float
    direction_deg: float
    start_length: float
    passes: ZonePasses
    lower_bound: float
    evaluations: int

    @property
    def length(self) -> float:
        return self.passes.length


@dataclass
class ZoningPlan:
    """Zones, their plans, and the Eq. 4 total; ``info`` holds method-specific facts."""

    method: str
    labels: np.ndarray
    zones: list[ZonePlan]
    delta_l: float
    seconds: dict[str, float]
    info: dict = field(default_factory=dict)
    features: MeshFeatures | None = None

    @property
    def cutting_length(self) -> float:
        return float(sum(z.length for z in self.zones))

    @property
    def penalty(self) -> float:
        return (len(self.zones) - 1) * self.delta_l

    @property
    def total_length(self) -> float:
        """Djebali Eq. 4: cutting length + (|Z| - 1) Delta L (mm)."""
        return self.cutting_length + self.penalty

    @property
    def link_length(self) -> float:
        return float(sum(z.passes.link_length for z in self.zones))


def zone_labels(features: MeshFeatures, method, seed: int = 0, **settings) -> tuple:
    """(labels (n, m), info dict) of a registered zoning method (a name or a ``ZoningMethod``)
    on the mesh features; ``settings`` are the method's (validated by its ``Settings``)."""
    zoning = get_method(method)
    return zoning.labels(features, zoning.settings(settings), seed=seed)


def plan_from_labels(samples: SurfaceSamples, features: MeshFeatures, labels: np.ndarray,
                     target: ScallopTarget, model: str = "profile", scan: int = 12) -> tuple[list[ZonePlan], float]:
    """Optimize every zone's direction; returns (zone plans, seconds)."""
    t0 = time.perf_counter()
    n, m = labels.shape
    cell_zone = labels.ravel()[samples.cell(n, m)]
    flat = labels.ravel()
    weight = (features.area * np.sin(features.slope)).ravel()
    steep = features.steepest.ravel()
    area = features.area.ravel()
    zones = []
    for z in range(int(labels.max()) + 1):
        in_zone = flat == z
        sub = samples.take(cell_zone == z)
        start = axial_mean(steep[in_zone], weight[in_zone])
        best = optimize_direction(sub, target, start, model=model, scan=scan)
        zones.append(ZonePlan(z, int(in_zone.sum()), float(area[in_zone].sum()),
                              float(np.degrees(start)), float(np.degrees(best.alpha)),
                              best.start_length, best.passes,
                              length_lower_bound(sub, target), best.evaluations))
    return zones, time.perf_counter() - t0


def plan_zones(surface: Surface, target: ScallopTarget, method: str = "kmeans",
               mesh=(70, 70), delta_l: float = 40.0, model: str = "profile",
               samples: SurfaceSamples | None = None, scan: int = 12, seed: int = 0,
               merge: MergeSettings | None = MergeSettings(), **settings) -> ZoningPlan:
    """The whole pipeline: features, zoning (``method`` with its ``settings``), merging
    (``merge``, default ``MergeSettings()``; None: the method's zones as they are), per-zone
    directions, Eq. 4 total."""
    delta_l = number(delta_l, "delta_l")
    if delta_l < 0:
        raise ValueError(f"delta_l: must be >= 0 mm, got {delta_l}")
    if model not in ("profile", "circle"):
        raise ValueError(f"stepover_model: expected profile or circle, got {model!r}")
    n, m = check_mesh(*mesh)
    t0 = time.perf_counter()
    samples = samples if samples is not None else sample_surface(surface)
    features = mesh_features(surface, n, m)
    t1 = time.perf_counter()
    zoning = get_method(method)
    if isinstance(merge, dict):
        try:
            merge = MergeSettings.model_validate(merge)
        except ValidationError as e:
            raise ValueError(one_line(e, "merge")) from None
    labels, info = zone_labels(features, zoning, seed=seed, **settings)
    if merge is not None:
        def zone_length(mask):  # Lg of one zone at its optimized direction (Eq. 4 term)
            one = plan_from_labels(samples, features, np.where(mask, 0, -1), target, model, scan)
            return one[0][0].length

        labels, info["merge"] = merge_zones(labels, features, merge, delta_l, zone_length)
    t2 = time.perf_counter()
    zones, t_dir = plan_from_labels(samples, features, labels, target, model, scan)
    seconds = {"features": t1 - t0, "zoning": t2 - t1, "directions": t_dir,
               "total": t2 - t0 + t_dir}
    return ZoningPlan(zoning.name, labels, zones, delta_l, seconds, info, features)
