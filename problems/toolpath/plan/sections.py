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
plan cuts every plane across the whole footprint. In a zoned plan a plane is cut wherever
its BAND holds zone material: the strip between its two neighbouring planes. Then every
point of the zone has both of the planes around it cut beside it (at its feed
coordinate), so the scallop between them is the one the spacing was chosen for, right up
to the zone's border: neighbouring zones' passes overlap there, by what the border's
obliquity to the planes requires and no more (a plane cut only where it crosses its zone
would leave a wedge between two planes that end at different places along an oblique
border). Membership is sampled along each plane at most ``resolution`` mm apart.

Each section also carries the gap its points' scallop is measured in: the spacing to the
next plane (``side`` +1), or to the previous one for the zone's last plane (-1), or none
for a zone of one plane (0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.rows import ranges
from .planes import PassGeometry

__all__ = ["Sections", "plane_offsets", "full_plane_sections", "zone_sections"]


@dataclass
class Sections:
    """Sections of one zone geometry (one feed direction ``alpha``, radians) for several
    individuals: per section its individual ``ind``, ``zone``, plane index ``pass_k``,
    offset ``d``, stretch [``ta``, ``tb``], maximum step ``step``, gap ``spacing``,
    ``side`` and the footprint's extent past its ends ``run_lo`` / ``run_hi``
    (:func:`edge_runs`)."""

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
    run_lo: np.ndarray
    run_hi: np.ndarray


def plane_offsets(lo, hi, delta):
    """Planes of k plans at XY step-over delta (k,) across extents [lo, hi] (k,):
    (owner, plane index, offset, gap, side), the last plane clamped on hi."""
    lo, hi, delta = (np.asarray(a, float) for a in (lo, hi, delta))
    width = np.maximum(hi - lo, 0.0)
    n_int = np.where(width > 0, np.maximum(np.ceil(width / delta - 1e-9), 1), 0).astype(int)
    owner, k = ranges(n_int + 1)
    d = lo[owner] + np.minimum(k * delta[owner], width[owner])
    return (owner, k, d) + _gaps(k, d, n_int[owner])


def _gaps(k, d, n_int):
    """(gap, side) of planes at offsets d, plane index k of n_int + 1 per owner."""
    last = k == n_int
    idx = np.arange(len(d))
    nxt, prv = np.minimum(idx + 1, len(d) - 1), np.maximum(idx - 1, 0)
    gap = np.where(last, d - d[prv], d[nxt] - d)
    side = np.where(n_int == 0, 0, np.where(last, -1, 1))
    return np.where(n_int == 0, 0.0, gap), side


def _band(k, gap, side):
    """(up, down): how far each plane's band reaches towards the next plane (along +c) and
    towards the previous one: the whole gap (measured on Choi's surface: half of it, each
    plane's own half-gap strip, left maxima of 0.32-0.40 mm at h_c 0.254 where the whole
    gap keeps them within 10 % of h_c)."""
    prev_gap = np.where(k > 0, np.r_[0.0, gap[:-1]], 0.0)
    return np.where(side > 0, gap, 0.0), np.where(side != 0, prev_gap, 0.0)


def edge_runs(geom: PassGeometry, d, up, down, samples: int = 4):
    """(run_lo, run_hi) (mm): how far the footprint extends along the feed past each plane's
    own ends within its band (the strip to its neighbouring planes). Where the part's edge
    is oblique to the planes, the neighbouring plane meets it later: the wedge of part
    between the two is only reached if this plane's pass runs on past its end by that much
    (``overrun.py``)."""
    lo, hi = geom.pass_extent(d)
    run_lo, run_hi = np.zeros_like(d), np.zeros_like(d)
    for f in np.arange(1, samples + 1) / samples:
        for off in (f * up, -f * down):
            lo2, hi2 = geom.pass_extent(d + off)
            run_lo = np.maximum(run_lo, lo - lo2)
            run_hi = np.maximum(run_hi, hi2 - hi)
    return run_lo, run_hi


def full_plane_sections(geom: PassGeometry, rows, delta, step) -> Sections:
    """Single zone: every plane across the whole footprint (``rows``: the individuals)."""
    rows = np.asarray(rows)
    n = len(rows)
    owner, k, d, gap, side = plane_offsets(np.full(n, geom.d_min), np.full(n, geom.d_max),
                                           delta)
    one = np.ones(len(d))
    run_lo, run_hi = edge_runs(geom, d, *_band(k, gap, side))
    return Sections(geom, float(np.arctan2(geom.f[1], geom.f[0])), rows[owner],
                    np.zeros(len(d), np.int64), k, d, 0 * one, one,
                    np.asarray(step, float)[owner], gap, side, run_lo, run_hi)


def zone_sections(geom: PassGeometry, layout, z: int, rows, delta, step, spacing: str,
                  resolution: float = 0.5, sub_planes: int = 4) -> Sections:
    """Zone z of ``layout`` for the individuals ``rows`` (their step-over ``delta`` and
    ``step``, mm): its planes (``spacing``: stepover | scallop) and their sections."""
    rows = np.asarray(rows)
    if spacing == "stepover":
        lo, hi = layout.extent[z]
        owner, k, d, gap, side = plane_offsets(np.full(len(rows), lo), np.full(len(rows), hi),
                                               delta)
        p, ta, tb = _stretches(geom, layout, z, d, gap, side, k, resolution, sub_planes)
        run_lo, run_hi = edge_runs(geom, d, *_band(k, gap, side))
    else:  # the same planes for every individual: one search, repeated
        planes = layout.planes[z]
        kk = np.arange(len(planes))
        d1 = planes
        gap1, side1 = _gaps(kk, d1, np.full(len(kk), len(planes) - 1))
        p1, ta1, tb1 = _stretches(geom, layout, z, d1, gap1, side1, kk, resolution, sub_planes)
        lo1, hi1 = edge_runs(geom, d1, *_band(kk, gap1, side1))
        owner, k = ranges(np.full(len(rows), len(planes)))
        d, gap, side, run_lo, run_hi = d1[k], gap1[k], side1[k], lo1[k], hi1[k]
        rep, _ = ranges(np.full(len(rows), len(p1)))
        p = np.tile(p1, len(rows)) + rep * len(planes)
        ta, tb = np.tile(ta1, len(rows)), np.tile(tb1, len(rows))
    alpha = float(np.arctan2(geom.f[1], geom.f[0]))
    return Sections(geom, alpha, rows[owner[p]], np.full(len(p), z, np.int64), k[p], d[p],
                    ta, tb, np.asarray(step, float)[owner[p]], gap[p], side[p],
                    run_lo[p], run_hi[p])


def _stretches(geom, layout, z, d, gap, side, k, resolution, sub_planes):
    """(plane, tau_a, tau_b) of every run along the planes d where the plane's BAND holds
    material of zone z: the band reaches the neighbouring planes (gap to the next, along +c,
    and to the previous), sampled by ``sub_planes`` offsets on each side, a point being
    zone material when its mesh cell carries the zone's label (the zone is its cells: a
    margin of half a sub-plane spacing plus half a cell measured 28-61 mm longer Choi plans
    with the same simulated scallops); along the planes the points are at most
    ``resolution`` mm apart in the feed coordinate."""
    up, down = _band(k, gap, side)
    lo, hi = geom.pass_extent(d)
    nt = max(int(np.ceil(float(np.max(hi - lo, initial=0.0)) / resolution)) + 1, 2)
    tau = np.linspace(0.0, 1.0, nt)
    s = lo[:, None] + tau[None, :] * (hi - lo)[:, None]  # feed coordinate (P, nt)
    n, m = layout.labels.shape
    frac = np.arange(1, sub_planes + 1) / sub_planes
    offsets = [np.zeros_like(d)] + [f * up for f in frac] + [-f * down for f in frac]
    inside = np.zeros((len(d), nt), bool)
    for off in offsets:
        d2 = d + off
        lo2, hi2 = geom.pass_extent(d2)
        span = np.where(hi2 > lo2, hi2 - lo2, 1.0)
        t2 = (s - lo2[:, None]) / span[:, None]
        ok = (t2 >= -1e-9) & (t2 <= 1 + 1e-9)
        u, v = geom.seed(np.repeat(d2, nt), t2.ravel())
        i = np.clip((u * n).astype(np.int64), 0, n - 1)
        j = np.clip((v * m).astype(np.int64), 0, m - 1)
        inside |= ok & (layout.labels[i, j].reshape(len(d), nt) == z)
    pad = np.pad(inside, ((0, 0), (1, 1)))
    starts = np.argwhere(pad[:, 1:-1] & ~pad[:, :-2])
    ends = np.argwhere(pad[:, 1:-1] & ~pad[:, 2:])
    half = 0.5 / (nt - 1)
    ta = np.clip(tau[starts[:, 1]] - half, 0.0, 1.0)
    tb = np.clip(tau[ends[:, 1]] + half, 0.0, 1.0)
    return starts[:, 0], ta, tb
