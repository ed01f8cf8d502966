"""A machining plan by zones: zoning, then per-zone direction, then Djebali Eq. 4.

    total = sum over zones of Lg(z, alpha_opt(z)) + (|Z| - 1) * Delta L     (Djebali Eq. 4)

Zoning methods come from the registry of ``methods/``: ``single`` (one zone: the
"straightforward" plan of Djebali Sec. 6.1), ``kmeans`` (Herraz's C4DO1D: ``kmeans.py``) and
``amas`` (Djebali's multi-agent system: ``amas.py``); any method's zones are then merged as
``merge.py`` explains (a minimum zone area, then Eq. 4 merging; ``merge=None``: none). Each
zone's direction is optimized on its own (``direction.py``) and its passes laid out by
``passes.py`` on the dense samples of ``samples.py``.

``label_zones`` (zoning and merging) and ``zone_direction`` (one zone's direction by a
``DirectionRule``) are the one implementation: ``plan_zones`` runs them, and so do the
planner's zone layouts (``plan/zones.py``) with their own rule.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from pydantic import ValidationError

from ...checks import number
from ...geometry.surface import Surface
from .direction import DirectionResult, axial_mean, optimize_direction
from .features import MeshFeatures, check_mesh, mesh_features
from .merge import MergeSettings, merge_zones
from .methods import get_method, method_names
from .methods.base import one_line
from .passes import ZonePasses, length_lower_bound, zone_passes
from .samples import SurfaceSamples, sample_surface
from .stepover import ScallopTarget

__all__ = ["METHODS", "ALPHA_STEP_DEG", "DirectionRule", "ZonePlan", "ZoningPlan", "zone_labels",
           "zone_direction", "label_zones", "plan_zones", "plan_from_labels"]

METHODS = method_names()  # the built-in methods; the registry (methods/) is the reference

#: optimized feed directions are searched to this tolerance and rounded to this grid
#: (degrees): layouts that share a direction share its pass-plane tables
ALPHA_STEP_DEG = 0.5


@dataclass(frozen=True)
class DirectionRule:
    """How each zone's feed direction is chosen: the fixed ``feed_angle`` (degrees from +X),
    or (None) Herraz Eq. 3 minimized from the zone's steepest-slope direction
    (``direction.optimize_direction`` with the step-over ``model``, ``scan`` and
    ``xatol_deg``), then rounded to the ``grid_deg`` grid (None: as found)."""

    model: str = "profile"
    scan: int = 12
    xatol_deg: float = ALPHA_STEP_DEG
    grid_deg: float | None = ALPHA_STEP_DEG
    feed_angle: float | None = None


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


def zone_direction(sub: SurfaceSamples, features: MeshFeatures, mask: np.ndarray,
                   target: ScallopTarget, rule: DirectionRule = DirectionRule()) -> DirectionResult:
    """The feed direction and passes of the zone of mesh cells ``mask`` (n, m), whose dense
    samples are ``sub``, by ``rule``."""
    if rule.feed_angle is not None:
        alpha = float(np.radians(rule.feed_angle)) % np.pi
        passes = zone_passes(sub, target, alpha, rule.model)
        return DirectionResult(alpha, passes, alpha, passes.length, 1)
    start = axial_mean(features.steepest[mask], (features.area * np.sin(features.slope))[mask])
    best = optimize_direction(sub, target, start, model=rule.model, scan=rule.scan,
                              xatol_deg=rule.xatol_deg)
    if rule.grid_deg is None:
        return best
    alpha = float(np.radians(rule.grid_deg * round(np.degrees(best.alpha) / rule.grid_deg)))
    alpha %= np.pi
    return DirectionResult(alpha, zone_passes(sub, target, alpha, rule.model), best.start,
                           best.start_length, best.evaluations)


def label_zones(features: MeshFeatures, samples: SurfaceSamples, method, target: ScallopTarget,
                *, seed: int = 0, merge: MergeSettings | None = MergeSettings(),
                delta_l: float = 40.0, rule: DirectionRule = DirectionRule(),
                **settings) -> tuple:
    """(labels (n, m), info): the zones of ``method`` (:func:`zone_labels`), then, when
    there are several, the merging of ``merge.py`` (None: none) with each candidate zone's
    Eq. 4 term Lg at its direction by ``rule``."""
    labels, info = zone_labels(features, method, seed=seed, **settings)
    if merge is None or labels.max() == 0:
        return labels, info
    cell_of = samples.cell(*labels.shape)

    def zone_length(mask):  # Lg of one candidate zone at its direction (Eq. 4 term)
        sub = samples.take(mask.ravel()[cell_of])
        return zone_direction(sub, features, mask, target, rule).passes.length

    labels, info["merge"] = merge_zones(labels, features, merge, delta_l, zone_length)
    return labels, info


def plan_from_labels(samples: SurfaceSamples, features: MeshFeatures, labels: np.ndarray,
                     target: ScallopTarget, rule: DirectionRule = DirectionRule()
                     ) -> tuple[list[ZonePlan], float]:
    """Every zone's direction by ``rule``; returns (zone plans, seconds)."""
    t0 = time.perf_counter()
    cell_zone = labels.ravel()[samples.cell(*labels.shape)]
    zones = []
    for z in range(int(labels.max()) + 1):
        mask = labels == z
        sub = samples.take(cell_zone == z)
        best = zone_direction(sub, features, mask, target, rule)
        zones.append(ZonePlan(z, int(mask.sum()), float(features.area[mask].sum()),
                              float(np.degrees(best.start)), float(np.degrees(best.alpha)),
                              best.start_length, best.passes,
                              length_lower_bound(sub, target), best.evaluations))
    return zones, time.perf_counter() - t0


def plan_zones(surface: Surface, target: ScallopTarget, method: str = "kmeans",
               mesh=(70, 70), delta_l: float = 40.0, model: str = "profile",
               samples: SurfaceSamples | None = None, scan: int = 12, seed: int = 0,
               merge: MergeSettings | None = MergeSettings(),
               rule: DirectionRule | None = None, **settings) -> ZoningPlan:
    """The whole pipeline: features, zoning (``method`` with its ``settings``), merging
    (``merge``, default ``MergeSettings()``; None: the method's zones as they are), per-zone
    directions (``rule``; default: the search's optimum as found, to 0.25 deg, not the
    planner's grid: rounding a direction near 180 deg to 0 lays the adaptive passes from
    the other side, which can end longer than the search's start), Eq. 4 total."""
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
    if rule is None:
        rule = DirectionRule(model=model, scan=scan, xatol_deg=0.25, grid_deg=None)
    labels, info = label_zones(features, samples, zoning, target, seed=seed, merge=merge,
                               delta_l=delta_l, rule=rule, **settings)
    t2 = time.perf_counter()
    zones, t_dir = plan_from_labels(samples, features, labels, target, rule)
    seconds = {"features": t1 - t0, "zoning": t2 - t1, "directions": t_dir,
               "total": t2 - t0 + t_dir}
    return ZoningPlan(zoning.name, labels, zones, delta_l, seconds, info, features)
