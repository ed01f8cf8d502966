"""Pass planes and their sections: where each plane of a zone is cut.

Planes are vertical and parallel to the zone's feed direction; a plane is its offset d
along the cross-feed c (``planes.PassGeometry``). Two spacings:

- **stepover** (Fountas et al.): d_k = lo + k delta across the zone's extent [lo, hi],
  delta = step-over % x D measured in XY between the planes, the last plane clamped on hi
  (its spacing may be shorter);
- **scallop** (Djebali et al. Sec. 3.1, Herraz et al. Sec. 3): the adaptive planes of the
  zone at h_c (``zones.ZoneLayout.planes``: each plane as far from the previous one as the
  worst point of its pass allows).

A section is a stretch [tau_a, tau_b] of a plane that the zone's passes cut. A single-zone
plan cuts every plane across the whole footprint. In a zoned plan a plane is cut where it
crosses the zone GROWN by the plane's own spacing (the larger of its two gaps), measured in
XY by the zone's distance field: then every point of the zone has both of its neighbouring
planes cut beside it, so the scallop between them is the scallop the spacing was chosen
for, right up to the zone's border (the neighbouring zones' passes overlap by about one
spacing, the price of a border that really meets the target). Membership is sampled along
each plane at most ``resolution`` mm apart.

Each section also carries the gap its points' scallop is measured in: the spacing to the
next plane (``side`` +1), or to the previous one for the zone's last plane (-1), or none
for a zone of one plane (0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .planes import PassGeometry
from .points import ranges

__all__ = ["Sections", "plane_offsets", "full_plane_sections", "zone_sections"]


@dataclass
class Sections:
    """Sections of one zone geometry (one feed direction ``alpha``, radians) for several
    individuals: per section its individual ``ind``, ``zone``, plane index ``pass_k``,
    offset ``d``, stretch [``ta``, ``tb``], maximum step ``step``, gap ``spacing`` and
    ``side``."""

    geom: PassGeometry
    alpha: float
    ind: np.ndarray
    zone: np.ndarray
    pass_k: np.ndarray
    d: np.ndarray
    ta: np.ndarray
    tb: np.ndarray
    step: np.ndarray
    spacing: np.ndarray
    side: np.ndarray


def plane_offsets(lo, hi, delta):
    """Planes of k plans at XY step-over delta (k,) across extents [lo, hi] (k,):
    (owner, plane index, offset, gap, side), the last plane clamped on hi."""
    lo, hi, delta = (np.asarray(a, float) for a in (lo, hi, delta))
    width = np.maximum(hi - lo, 0.0)
    n_int = np.where(width > 0, np.maximum(np.ceil(width / delta - 1e-9), 1), 0).astype(int)
    owner, k = ranges(n_int + 1)
    d = lo[owner] + np.minimum(k * delta[owner], width[owner])
    return (owner, k) + _gaps(owner, k, d, n_int[owner])


def _gaps(owner, k, d, n_int):
    """(offsets, gap, side) of planes given plane index k of n_int + 1 per owner."""
    last = k == n_int
    idx = np.arange(len(d))
    nxt, prv = np.minimum(idx + 1, len(d) - 1), np.maximum(idx - 1, 0)
    gap = np.where(last, d - d[prv], d[nxt] - d)
    side = np.where(n_int == 0, 0, np.where(last, -1, 1))
    return d, np.where(n_int == 0, 0.0, gap), side


def full_plane_sections(geom: PassGeometry, rows, delta, step) -> Sections:
    """Single zone: every plane across the whole footprint (``rows``: the individuals)."""
    rows = np.asarray(rows)
    n = len(rows)
    owner, k, d, gap, side = plane_offsets(np.full(n, geom.d_min), np.full(n, geom.d_max),
                                           delta)
    one = np.ones(len(d))
    return Sections(geom, float(np.arctan2(geom.f[1], geom.f[0])), rows[owner],
                    np.zeros(len(d), np.int64), k, d, 0 * one, one,
                    np.asarray(step, float)[owner], gap, side)


def zone_sections(geom: PassGeometry, layout, z: int, rows, delta, step, spacing: str,
                  resolution: float = 0.5) -> Sections:
    """Zone z of ``layout`` for the individuals ``rows`` (their step-over ``delta`` and
    ``step``, mm): its planes (``spacing``: stepover | scallop) and their sections."""
    rows = np.asarray(rows)
    if spacing == "stepover":
        lo, hi = layout.extent[z]
        owner, k, d, gap, side = plane_offsets(np.full(len(rows), lo), np.full(len(rows), hi),
                                               delta)
    else:
        planes = layout.planes[z]
        n_int = len(planes) - 1
        owner, k = ranges(np.full(len(rows), len(planes)))
        d, gap, side = _gaps(owner, k, np.tile(planes, len(rows)), np.full(len(k), n_int))
    prev_gap = np.where(k > 0, np.r_[0.0, gap[:-1]], 0.0)
    grow = np.maximum(np.where(side > 0, gap, 0.0), np.where(side != 0, prev_gap, 0.0))
    grow = grow + 0.5 * max(layout.cell_size)
    p, ta, tb = _stretches(geom, layout, z, d, grow, resolution)
    alpha = float(np.arctan2(geom.f[1], geom.f[0]))
    return Sections(geom, alpha, rows[owner[p]], np.full(len(p), z, np.int64), k[p], d[p],
                    ta, tb, np.asarray(step, float)[owner[p]], gap[p], side[p])


def _stretches(geom, layout, z, d, grow, resolution):
    """(plane, tau_a, tau_b) of every run of plane points within ``grow`` (mm, per plane)
    of zone z, sampled at most ``resolution`` mm apart along the planes."""
    lo, hi = geom.pass_extent(d)
    nt = max(int(np.ceil(float(np.max(hi - lo, initial=0.0)) / resolution)) + 1, 2)
    tau = np.linspace(0.0, 1.0, nt)
    u, v = geom.seed(np.repeat(d, nt), np.tile(tau, len(d)))
    n, m = layout.labels.shape
    i = np.clip((u * n).astype(np.int64), 0, n - 1)
    j = np.clip((v * m).astype(np.int64), 0, m - 1)
    inside = (layout.distance[z][i, j] <= np.repeat(grow, nt)).reshape(len(d), nt)
    pad = np.pad(inside, ((0, 0), (1, 1)))
    starts = np.argwhere(pad[:, 1:-1] & ~pad[:, :-2])
    ends = np.argwhere(pad[:, 1:-1] & ~pad[:, 2:])
    half = 0.5 / (nt - 1)
    ta = np.clip(tau[starts[:, 1]] - half, 0.0, 1.0)
    tb = np.clip(tau[ends[:, 1]] + half, 0.0, 1.0)
    return starts[:, 0], ta, tb
