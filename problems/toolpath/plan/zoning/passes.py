"""Parallel-plane passes restricted to one zone, and the zone's path length.

Strategy (Djebali et al. Sec. 1 and 3.1; Herraz et al. Sec. 3, the zig-zag parallel planes):
the CC paths of a zone are its sections by vertical planes parallel to the feed direction
alpha. With f = (cos a, sin a) and c = (-sin a, cos a), a plane is {c . (x, y) = s}.

- **Plane placement** (Herraz Sec. 3): the first plane touches the zone's edge (s_min); the
  next one is as far as the WORST point of the current pass allows,
  s_{k+1} = s_k + min over the pass of d (``stepover.plane_spacing``: the scallop stays
  under h_c everywhere on the pass), and as far as the worst point of the cusp line
  halfway between the two planes allows (where the scallop stands: the spacing of the
  pass alone left cusps of 0.28-0.30 mm at h_c 0.254 on Choi's surface, torus r 1, 0.05
  mm grid, mostly where a zone's passes meet its border, against <= 0.276 mm with the
  cusp line checked; ``runs/reproduce/run_files_h_c.md``); the last plane is clamped on
  the far edge s_max. The points "on" a line are the samples within one sample spacing
  of it.
- **Pass length**: each sample belongs to its nearest plane; a pass runs over every stretch
  of the feed coordinate t = f . (x, y) where its band holds zone material (binned at
  1.5 sample spacings), so no material of a jagged zone between two planes is left out.
  The length is measured on the surface: dt sqrt(1 + (grad z . f)^2).
- Links between passes inside a zone are reported apart (their horizontal length, the
  plane spacings); the zone length of Djebali Eq. 4 is the cutting length.

Lower bound (``length_lower_bound``): a pass clears a strip at most w_cap wide and the path
is at least its XY length, so no plan of a zone is shorter than area_xy / w_cap.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .samples import SurfaceSamples
from .stepover import ScallopTarget, plane_spacing

__all__ = ["ZonePasses", "zone_passes", "zone_length", "length_lower_bound"]


@dataclass(frozen=True)
class ZonePasses:
    """Planes (offsets ``s`` along c, mm) and per-pass cutting lengths on the surface."""

    alpha: float
    s: np.ndarray
    lengths: np.ndarray
    spacing: np.ndarray

    @property
    def length(self) -> float:
        """Cutting length of the zone (mm)."""
        return float(self.lengths.sum())

    @property
    def link_length(self) -> float:
        """Horizontal length of the step moves between consecutive passes (mm)."""
        return float(np.diff(self.s).sum()) if len(self.s) > 1 else 0.0


#: rounds of the cusp-line check of ``_place_planes`` (each can only shorten the step)
CUSP_ROUNDS = 3


def _place_planes(s_sorted, d_sorted, band: float, max_planes: int) -> np.ndarray:
    """Plane offsets from lo to hi (the samples' offsets ``s_sorted``, their largest
    spacings ``d_sorted``): each step the smallest spacing of the samples on the current
    plane AND on the cusp line halfway to the next one (``band``: the half-width of a
    line's samples), the halfway line re-found after each shortening (``CUSP_ROUNDS``)."""
    lo, hi = float(s_sorted[0]), float(s_sorted[-1])
    planes = [lo]
    s_k = lo
    while s_k < hi and len(planes) < max_planes:
        a = np.searchsorted(s_sorted, s_k - band, side="left")
        b = np.searchsorted(s_sorted, s_k + band, side="right")
        if b > a:
            step = float(d_sorted[a:b].min())
        else:  # no sample on this plane (a gap in the sampling): use the next samples
            step = float(d_sorted[b:b + 8].min())
        for _ in range(CUSP_ROUNDS):
            m0 = np.searchsorted(s_sorted, s_k + 0.5 * step - band, side="left")
            m1 = np.searchsorted(s_sorted, s_k + 0.5 * step + band, side="right")
            if m1 <= m0 or float(d_sorted[m0:m1].min()) >= step:
                break
            step = float(d_sorted[m0:m1].min())
        s_k = s_k + step
        planes.append(min(s_k, hi))
    return np.asarray(planes)


def zone_passes(s: SurfaceSamples, target: ScallopTarget, alpha: float, model: str = "profile",
                max_planes: int = 100_000) -> ZonePasses:
    """Passes of the zone sampled by ``s`` along ``alpha`` (radians); see the module doc.

    ``model``: the step-over model of ``stepover.plane_spacing`` ("profile" or "circle").
    """
    if len(s) == 0:
        return ZonePasses(float(alpha), np.zeros(0), np.zeros(0), np.zeros(0))
    fx, fy = np.cos(alpha), np.sin(alpha)
    off = -fy * s.x + fx * s.y
    t = fx * s.x + fy * s.y
    d = plane_spacing(s, target, alpha, model)
    order = np.argsort(off, kind="stable")
    planes = _place_planes(off[order], d[order], s.spacing, max_planes)
    if len(planes) > 1:
        mids = 0.5 * (planes[1:] + planes[:-1])
        owner = np.searchsorted(mids, off)
    else:
        owner = np.zeros(len(off), np.int64)
    dt = 1.5 * s.spacing
    tbin = np.floor((t - t.min()) / dt).astype(np.int64)
    nt = int(tbin.max()) + 1
    key = owner * nt + tbin
    stretch = np.sqrt(1.0 + (s.p * fx + s.q * fy) ** 2)
    count = np.bincount(key, minlength=len(planes) * nt)
    total = np.bincount(key, weights=stretch, minlength=len(planes) * nt)
    occupied = count > 0
    per_bin = np.where(occupied, total / np.maximum(count, 1), 0.0) * dt
    lengths = per_bin.reshape(len(planes), nt).sum(axis=1)
    return ZonePasses(float(alpha), planes, lengths, np.diff(planes))


def zone_length(s: SurfaceSamples, target: ScallopTarget, alpha: float,
                model: str = "profile") -> float:
    """Cutting length (mm) of the zone along ``alpha``: the black box of Herraz Eq. 3."""
    return zone_passes(s, target, alpha, model).length


def length_lower_bound(s: SurfaceSamples, target: ScallopTarget) -> float:
    """No plan of this zone is shorter than its XY area over the widest step w_cap (mm)."""
    return float(s.area_xy.sum()) / target.width_cap
