"""Per-zone feed direction: a bounded 1-D black-box minimization of the zone's path length.

Herraz Eq. 3: min over Theta_k of machining_time(Theta_k), one zone at a time, the path
length simulated by ``passes.zone_length`` (a black box: piecewise smooth, with jumps when
a pass appears or disappears). Started, as Herraz advises, from the zone's overall
steepest-slope direction: the axial mean of the cells' directions, weighted by area x
sin(slope) (flat cells have no direction). The optimizer is scipy's bounded Brent
(``minimize_scalar(method="bounded")``); because the length has several local minima over
the half-turn of feed directions, it first evaluates the start and ``scan`` directions
spread over [start - 90, start + 90) degrees and then refines inside the bracket around the
best of them. The best evaluated direction is returned (never worse than the start).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from .passes import ZonePasses, zone_passes
from .samples import SurfaceSamples
from .stepover import ScallopTarget

__all__ = ["DirectionResult", "axial_mean", "optimize_direction"]


@dataclass(frozen=True)
class DirectionResult:
    """Best direction (radians, in [0, pi)), its passes, the start and the evaluations used."""

    alpha: float
    passes: ZonePasses
    start: float
    start_length: float
    evaluations: int


def axial_mean(angles, weights) -> float:
    """Mean of axial angles (mod pi) with weights, by doubled angles; in [0, pi)."""
    a = np.asarray(angles, float)
    w = np.asarray(weights, float)
    c, s = (w * np.cos(2 * a)).sum(), (w * np.sin(2 * a)).sum()
    if c == 0 and s == 0:
        return 0.0
    return float(np.mod(0.5 * np.arctan2(s, c), np.pi))


def optimize_direction(s: SurfaceSamples, target: ScallopTarget, start: float,
                       model: str = "profile", scan: int = 12, xatol_deg: float = 0.25,
                       max_evaluations: int = 60) -> DirectionResult:
    """Minimize the zone's cutting length over the feed direction (see the module doc)."""
    cache: dict[float, ZonePasses] = {}

    def length(alpha: float) -> float:
        key = float(np.mod(alpha, np.pi))
        if key not in cache:
            cache[key] = zone_passes(s, target, key, model)
        return cache[key].length

    start = float(np.mod(start, np.pi))
    start_length = length(start)
    step = np.pi / max(scan, 1)
    grid = start - 0.5 * np.pi + step * np.arange(max(scan, 1))
    values = [length(a) for a in grid]
    best = float(grid[int(np.argmin(values))])
    if scan > 1:
        minimize_scalar(length, bounds=(best - step, best + step), method="bounded",
                        options={"xatol": np.radians(xatol_deg),
                                 "maxiter": max(1, max_evaluations - len(cache))})
    alpha = min(cache, key=lambda a: cache[a].length)
    return DirectionResult(alpha, cache[alpha], start, start_length, len(cache))
