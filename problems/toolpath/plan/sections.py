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

A plane may cross a trimmed or non-convex footprint several times (a hole, a notch): each
stretch between an entry and the next exit is a section of its own (``planes.material``),
so no CC point lies off the part; a zoned plane's stretches are cut down to them. Sections
of one plane are machined in order along it (reversed on a reversed plane) and linked as
any two sections are. ``edge_lo`` / ``edge_hi`` say which ends lie on the footprint's edge
(the travel runs on past them, ``overrun.py``) and how far along an oblique edge
(``run_lo`` / ``run_hi``, :func:`stretch_runs`).

Each section also carries the gap its points' scallop is measured in: the spacing to the
next plane (``side`` +1), or to the previous one for the zone's last plane (-1), or none
for a zone of one plane (0).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.rows import ranges
from .planes import PassGeometry
from .seed_kernel import band_inside, band_runs, band_runs_max, zone_cells

__all__ = ["Sections", "plane_offsets", "stretch_runs", "full_plane_sections", "zone_sections",
           "layout_zone_cells"]


@dataclass
class Sections:
    """Sections of one zone geometry (one feed direction ``alpha``, radians) for several
    individuals: per section its individual ``ind``, ``zone``, plane index ``pass_k``,
    offset ``d``, stretch [``ta``, ``tb``], maximum step ``step``, gap ``spacing``,
    ``side``, the footprint's extent past its ends ``run_lo`` / ``run_hi``
    (:func:`edge_runs`) and whether each end lies on the footprint's edge (``edge_lo``,
    ``edge_hi``)."""

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
    edge_lo: np.ndarray
    edge_hi: np.ndarray


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
    c = np.ascontiguousarray
    return band_runs_max(geom.d_grid, geom.s_lo, geom.s_hi, c(d, float), c(up, float),
                         c(down, float), np.arange(1, samples + 1) / samples)


def edge_runs_numpy(geom: PassGeometry, d, up, down, samples: int = 4):
    """:func:`edge_runs` in numpy (the reference its compiled pass,
    ``seed_kernel.band_runs_max``, is tested against)."""
    lo, hi = geom.pass_extent_numpy(d)
    run_lo, run_hi = np.zeros_like(d), np.zeros_like(d)
    offs = [off for f in np.arange(1, samples + 1) / samples for off in (f * up, -f * down)]
    lo_all, hi_all = geom.pass_extent_numpy(np.stack([d + off for off in offs]))
    for lo2, hi2 in zip(lo_all, hi_all):
        run_lo = np.maximum(run_lo, lo - lo2)
        run_hi = np.maximum(run_hi, hi2 - hi)
    return run_lo, run_hi


def stretch_runs(geom: PassGeometry, d, up, down, samples: int = 4):
    """The footprint's stretches of planes d (``planes.material``) and how far the footprint
    runs on past each stretch's ends within its plane's band: (plane, tau_a, tau_b, run_lo,
    run_hi), runs in mm. On the whole square a plane is one stretch and the runs are
    :func:`edge_runs`; on a trimmed footprint a neighbouring plane's stretch counts only where
    it overlaps this one along the feed (a notch or a hole beyond is not the wedge of this
    edge: the outer extents would run the tool on across it)."""
    line, ta, tb, _, _ = geom.material(d)
    if geom.loops_sd is None:
        run_lo, run_hi = edge_runs(geom, d, up, down, samples)
        return line, ta, tb, run_lo[line], run_hi[line]
    sa, sb = _feed(geom, d[line], ta, tb)
    run_lo, run_hi = np.zeros(len(line)), np.zeros(len(line))
    for f in np.arange(1, samples + 1) / samples:
        for off in (f * up, -f * down):
            d2 = d + off
            n_line, na, nb, _, _ = geom.material(d2)
            na, nb = _feed(geom, d2[n_line], na, nb)
            count = np.bincount(n_line, minlength=len(d))
            r, j = ranges(count[line])  # every (stretch, neighbour's stretch) pair
            m = np.cumsum(count)[line[r]] - count[line[r]] + j
            over = (na[m] < sb[r]) & (nb[m] > sa[r])
            np.maximum.at(run_lo, r[over], sa[r[over]] - na[m[over]])
            np.maximum.at(run_hi, r[over], nb[m[over]] - sb[r[over]])
    return line, ta, tb, run_lo, run_hi


def _feed(geom, d, ta, tb):
    """Feed coordinates (mm) of the stretch ends tau_a, tau_b of planes d."""
    lo, hi = geom.pass_extent(d)
    return lo + ta * (hi - lo), lo + tb * (hi - lo)


def full_plane_sections(geom: PassGeometry, rows, delta, step) -> Sections:
    """Single zone: every plane across the whole footprint (``rows``: the individuals), a
    plane that crosses a trimmed footprint several times in as many sections."""
    rows = np.asarray(rows)
    n = len(rows)
    owner, k, d, gap, side = plane_offsets(np.full(n, geom.d_min), np.full(n, geom.d_max),
                                           delta)
    p, ta, tb, run_lo, run_hi = stretch_runs(geom, d, *_band(k, gap, side))
    edge = np.ones(len(p), bool)
    return Sections(geom, float(np.arctan2(geom.f[1], geom.f[0])), rows[owner[p]],
                    np.zeros(len(p), np.int64), k[p], d[p], ta, tb,
                    np.asarray(step, float)[owner[p]], gap[p], side[p], run_lo, run_hi,
                    edge, edge)


def zone_sections(geom: PassGeometry, layout, z: int, rows, delta, step, spacing: str,
                  resolution: float = 0.5, sub_planes: int = 4) -> Sections:
    """Zone z of ``layout`` for the individuals ``rows`` (their step-over ``delta`` and
    ``step``, mm): its planes (``spacing``: stepover | scallop) and their sections."""
    rows = np.asarray(rows)
    if spacing == "stepover":
        lo, hi = layout.extent[z]
        owner, k, d, gap, side = plane_offsets(np.full(len(rows), lo), np.full(len(rows), hi),
                                               delta)
        p, ta, tb, e_lo, e_hi, run_lo, run_hi = _stretches(geom, layout, z, d, gap, side, k,
                                                           resolution, sub_planes)
    else:  # the same planes for every individual: one search, repeated
        planes = layout.planes[z]
        kk = np.arange(len(planes))
        d1 = planes
        gap1, side1 = _gaps(kk, d1, np.full(len(kk), len(planes) - 1))
        p1, *per = _stretches(geom, layout, z, d1, gap1, side1, kk, resolution, sub_planes)
        owner, k = ranges(np.full(len(rows), len(planes)))
        d, gap, side = d1[k], gap1[k], side1[k]
        rep, _ = ranges(np.full(len(rows), len(p1)))
        p = np.tile(p1, len(rows)) + rep * len(planes)
        ta, tb, e_lo, e_hi, run_lo, run_hi = (np.tile(a, len(rows)) for a in per)
    alpha = float(np.arctan2(geom.f[1], geom.f[0]))
    return Sections(geom, alpha, rows[owner[p]], np.full(len(p), z, np.int64), k[p], d[p],
                    ta, tb, np.asarray(step, float)[owner[p]], gap[p], side[p],
                    run_lo, run_hi, e_lo, e_hi)


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
    frac = np.arange(1, sub_planes + 1) / sub_planes
    offsets = [np.zeros_like(d)] + [f * up for f in frac] + [-f * down for f in frac]
    d2 = np.stack([d + off for off in offsets])  # (sub-plane offsets, P)
    lo2, hi2 = geom.pass_extent(d2)
    span = np.where(hi2 > lo2, hi2 - lo2, 1.0)
    inside = band_inside(geom.d_grid, geom.U, geom.V, layout.labels, z, s, d2, lo2, span,
                         layout_zone_cells(geom, layout, z))
    half = 0.5 / (nt - 1)
    if geom.loops_sd is None:  # one stretch a plane: one compiled pass
        return band_runs(inside, tau, half, *edge_runs(geom, d, up, down))
    return _band_runs_numpy(geom, d, inside, tau, half, up, down)


def _band_runs_numpy(geom, d, inside, tau, half, up, down):
    """The runs of ``inside`` (P, nt) along planes d, widened by ``half`` and cut to the
    footprint's stretches (:func:`_on_material`); on a whole footprint the numbers of
    ``seed_kernel.band_runs``, its reference."""
    pad = np.pad(inside, ((0, 0), (1, 1)))
    starts = np.argwhere(pad[:, 1:-1] & ~pad[:, :-2])
    ends = np.argwhere(pad[:, 1:-1] & ~pad[:, 2:])
    ta = np.clip(tau[starts[:, 1]] - half, 0.0, 1.0)
    tb = np.clip(tau[ends[:, 1]] + half, 0.0, 1.0)
    return _on_material(geom, d, starts[:, 0], ta, tb, up, down)


def layout_zone_cells(geom, layout, z):
    """``seed_kernel.zone_cells`` of zone z on geom's tables, memoized in the layout (it
    depends on the layout and the feed direction alone, not on the genes)."""
    memo = layout.__dict__.setdefault("_zone_cells", {})
    key = (z, float(geom.f[0]), float(geom.f[1]), geom.U.shape)  # the direction's tables
    if key not in memo:
        memo[key] = zone_cells(geom.U, geom.V, layout.labels, z)
    return memo[key]


def _band_inside_numpy(geom, labels, z, s, d2, lo2, span):
    """``seed_kernel.band_inside`` in numpy (the reference the compiled pass is tested
    against): (P, nt) whether some sub-plane offset's sample of each plane lies within its
    extent and in a mesh cell labelled z."""
    n, m = labels.shape
    P, nt = s.shape
    inside = np.zeros((P, nt), bool)
    for o in range(len(d2)):
        t2 = (s - lo2[o][:, None]) / span[o][:, None]
        ok = (t2 >= -1e-9) & (t2 <= 1 + 1e-9)
        u, v = geom.seed_numpy(np.repeat(d2[o], nt), t2.ravel())
        i = np.clip((u * n).astype(np.int64), 0, n - 1)
        j = np.clip((v * m).astype(np.int64), 0, m - 1)
        inside |= ok & (labels[i, j].reshape(P, nt) == z)
    return inside


def _on_material(geom, d, plane, ta, tb, up, down):
    """The runs [ta, tb] of planes ``d[plane]`` cut down to the footprint's stretches of
    their planes (:func:`stretch_runs`): (plane, ta, tb, edge_lo, edge_hi, run_lo, run_hi),
    an end on the edge where the footprint's stretch ends it (within 1e-9), with that
    stretch's run-on there (0 at an end inside the part)."""
    m_line, m_a, m_b, m_run_lo, m_run_hi = stretch_runs(geom, d, up, down)
    count = np.bincount(m_line, minlength=len(d))
    m_start = np.cumsum(count) - count
    run, j = ranges(count[plane])  # every (run, stretch of its plane) pair
    m = m_start[plane[run]] + j
    lo, hi = np.maximum(ta[run], m_a[m]), np.minimum(tb[run], m_b[m])
    keep = hi > lo
    run, m, lo, hi = run[keep], m[keep], lo[keep], hi[keep]
    e_lo, e_hi = m_a[m] >= ta[run] - 1e-9, m_b[m] <= tb[run] + 1e-9
    return (plane[run], lo, hi, e_lo, e_hi, np.where(e_lo, m_run_lo[m], 0.0),
            np.where(e_hi, m_run_hi[m], 0.0))
