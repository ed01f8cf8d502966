"""``isoscallop``: each pass offset from the previous one, point by point, by the cross-feed
distance that leaves exactly the scallop target h_c there.

Per zone (the planner's zone layout: labels, feed direction alpha, adaptive planes):

- **Master pass**: the section of the footprint by the zone's first parallel plane (the
  plane at the zone's edge along its optimized direction alpha, ``zones.ZoneLayout.planes``)
  or the plane at ``master_offset`` mm along the cross-feed c = (-sin a, cos a). Why this
  and not the zone's border: the border of a zone is a staircase of mesh cells, whose
  offsets fold at every step, while the plane section is smooth and is fed along the
  direction Herraz Eq. 3 chose for the zone (the best effective radius); on a plane the
  offsets of a plane section are planes, so ``isoscallop`` then equals ``parallel`` at the
  closed-form spacing (tested).
- **Next pass**: from every point of the pass, a walk on the surface along the cross-feed
  tangent b = n x t (oriented towards +c) by the width w that leaves a cusp of h_c
  between the two passes there. 3-axis: w is this pass's +b half-width plus the next
  pass's half-width on its side facing back, each the exact swept profile of the vertical
  cutter on that side with the curvature across the feed to second order
  (``offsets.facing_width``; a torus's two sides differ: corner arc uphill, flat bottom
  downhill), the next pass's frame taken where w puts it (twice); then checked against the
  two passes' real sweeps over the surface between them (``offsets.cusp_heights``: the
  model's one curvature and straight passes fail on ridges and bends) and narrowed where
  they leave more than h_c (three times). 5-axis: the cutter's profile swept at the plan's
  lead and tilt against the normal curvature, the analytic criteria's model
  (``offsets.profile_cross_width``). Widths are smoothed along the pass without
  ever exceeding a raw width within +-2 mm.
- **Clean-up**: the loops of the new pass (the swallowtail where the pass bends towards
  its offsets) are cut out at their crossing (``offsets.untangle``), and a corner pass runs
  from the sharp corner the cut leaves back to the bend when that is farther than
  ``CORNER_GAPS`` gaps (:func:`_corner_passes`, after the passes of that side); the pass is
  resampled every ``resample`` mm of arc; points past the footprint are clipped, keeping
  the crossing point on the edge; the propagation stops when no point is left. On a
  trimmed footprint (a CAD face's hole or notch) the passes are cut where they leave its
  loops (``Footprint.contains``; ends there on the part's edge: the travel runs on past
  them) and propagate on across the hole.
- **Zone**: a pass is cut wherever it or its offset lies in the zone (the band rule of
  parallel planes: the two passes around every zone point are cut beside it, so zoned
  plans keep cutting their borders), run on half the cutter's radius past it (the next
  zone's passes meet these at an angle: the triangles between their ends stay uncut
  otherwise); where a pass's offset leaves the footprint, the
  stretch of edge between them is cut as a **border pass** (the last pass on the border).

Passes depend only on (zone layout, tool, h_c, and for 5-axis lead/tilt): memoized.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import maximum_filter1d, minimum_filter1d, uniform_filter1d

from ...geometry.footprint import footprint_of
from ...geometry.surface import unit_normal
from ..curves import Piece
from ..zoning.stepover import ScallopTarget
from .base import CurveStrategy
from .offsets import (cross_width, cusp_heights, extend_to_edge, facing_width, march,
                      pass_frame, resample, runs, side_of, untangle, zone_mask)

__all__ = ["IsoScallop", "zone_passes"]

#: a swallowtail's corner gets a corner pass when it lies farther than this many gaps from
#: the bend it came from (an even ball's worst point between them is then 2 D / (D + gap)
#: half-gaps from both passes, D the distance: 1.11 at 1.25 gaps; the gaps are the smallest
#: within 2 mm along the pass, so the real cusp is lower. On Choi's torus plan 1.05 added
#: 29 corner passes, 1.25 12, and no scallop changed; on the sample STEP block 1.5 leaves
#: 0.069 mm against h_c 0.05 at a corner, 1.25 none)
CORNER_GAPS = 1.25


def _master(planner, layout, z, offset, ds, key):
    alpha = layout.alpha[z]
    lo, hi = layout.extent[z]
    if offset is None:  # the plane through the middle of the zone's cells
        geom = planner.geometry(alpha)
        n, m = layout.labels.shape
        i, j = np.nonzero(layout.labels == z)
        p = planner.surface.jet((i + 0.5) / n, (j + 0.5) / m, order=0).p
        d0 = float(np.median(p[:, :2] @ geom.c))
    else:
        d0 = float(offset)
        if not lo - 1e-9 <= d0 <= hi + 1e-9:
            raise ValueError(f"{key}.master_offset: {d0:g} mm lies outside zone {z}'s extent "
                             f"[{lo:.3f}, {hi:.3f}] mm across its feed")
    geom = planner.geometry(alpha)
    s_lo, s_hi = geom.pass_extent(np.array([d0]))
    k = max(int(np.ceil((s_hi[0] - s_lo[0]) / ds)), 2) + 1
    u, v, _ = geom.locate(np.full(k, d0), np.linspace(0.0, 1.0, k), iters=2)
    return np.column_stack([u, v])


def zone_passes(planner, layout, z, cutter, h_c, lead_tilt=None, offset=None, ds=0.5,
                max_passes=2000, key="strategy"):
    """The passes of zone z: [[Piece]] per pass in machining order across the zone (each
    along +f, before the zig-zag): from the master pass outwards to both sides, the -c side
    first (farthest pass first), or to +c only from a ``master_offset`` plane."""
    master = resample(planner.surface, extend_to_edge(
        _master(planner, layout, z, offset, ds, key)), ds)
    plus = _propagate(planner, layout, z, cutter, h_c, lead_tilt, master, +1.0, ds, max_passes)
    passes = plus
    if offset is None:
        passes = _propagate(planner, layout, z, cutter, h_c, lead_tilt, master, -1.0, ds,
                            max_passes)[1:][::-1] + plus
    for k, pieces in enumerate(passes):  # passes numbered across the zone in cutting order
        for pc in pieces:
            pc.pass_k = k
    return passes


def _propagate(planner, layout, z, cutter, h_c, lead_tilt, master, sign, ds, max_passes,
               window=2.0, settle=2):
    surface, alpha = planner.surface, layout.alpha[z]
    fp = footprint_of(surface)
    c0 = sign * np.array([-np.sin(alpha), np.cos(alpha), 0.0])
    front = [master]
    out, corners = [], []
    for k in range(max_passes):
        pieces, new_front, border = [], [], []
        for uv in front:
            if len(uv) < 2:
                continue
            jet, n, t, b = pass_frame(surface, uv)
            b *= np.where(b[:, :2] @ c0[:2] >= 0, 1.0, -1.0)[:, None]
            size = 2 * int(round(window / ds)) + 1
            if lead_tilt is None:
                w = _facing_widths(surface, cutter, h_c, uv, jet, t, b, size, settle)
            else:
                w = _smooth(cross_width(surface, cutter, h_c, jet, t, b, lead_tilt), size)
            nxt = march(surface, uv, b, w)
            p_new = surface.jet(nxt[:, 0], nxt[:, 1], order=0).p
            dxy = p_new[:, :2] - jet.p[:, :2]
            gap = np.linalg.norm(dxy, axis=1)
            cross = np.column_stack([dxy / np.maximum(gap, 1e-300)[:, None],
                                     np.zeros(len(uv))])
            in_box = np.all((nxt >= 0) & (nxt <= 1), axis=1)
            here = zone_mask(layout.labels, z, uv)
            band = here | (zone_mask(layout.labels, z, nxt) & in_box)
            if not band.all():  # run on past the zone's border by half the cutter's
                # radius: the next zone's passes meet these at an angle, and the triangles
                # between their ends would stay uncut
                band = maximum_filter1d(band.astype(np.int8), 2 * int(np.ceil(
                    0.5 * cutter.radius / ds)) + 1, mode="nearest").astype(bool)
            on = np.ones(len(uv), bool) if fp.whole else fp.contains(uv[:, 0], uv[:, 1])
            for a, e in runs(band & on):  # a trimmed footprint: cut at its loops too, the
                # ends there on the part's edge (the travel runs on past them)
                pieces.append(Piece(uv[a:e], cross[a:e], gap[a:e], z, k, alpha,
                                    (a > 0 and not on[a - 1], e < len(uv) and not on[e])))
            for a, e in runs(~in_box & here):  # the offset leaves the footprint: the edge
                edge = np.clip(nxt[a:e], 0.0, 1.0)
                keep = np.ones(len(edge), bool) if fp.whole else fp.contains(*edge.T)
                for a2, e2 in runs(keep):
                    if e2 - a2 >= 2:
                        border.append(Piece(edge[a2:e2], np.zeros((e2 - a2, 3)),
                                            np.zeros(e2 - a2), z, k + 1, alpha, (True, True)))
            # the next front: its loops cut out (the swallowtail where this pass bends
            # towards its offsets: the corner left is where the two arms meet), clipped to
            # the footprint (crossings kept)
            keep = in_box.copy()
            keep[:-1] |= in_box[1:]
            keep[1:] |= in_box[:-1]
            cut = []
            for a, e in runs(keep):
                if e - a < 2:
                    continue
                here_cut = []
                new_front.append(resample(surface, extend_to_edge(
                    np.clip(untangle(nxt[a:e], crossings=here_cut), 0.0, 1.0)), ds))
                cut += [(c, a + i) for c, i in here_cut]
            corners += _corner_passes(surface, layout, z, fp, uv, w, cut, k, alpha, ds)
        for pc in pieces:
            pc.edge = (pc.edge[0] or bool(np.any((pc.uv[0] <= 1e-7) | (pc.uv[0] >= 1 - 1e-7))),
                       pc.edge[1] or bool(np.any((pc.uv[-1] <= 1e-7) | (pc.uv[-1] >= 1 - 1e-7))))
        if pieces:
            out.append(pieces)
        if border:
            out.append(border)
        front = [f for f in new_front if np.any(np.all((f > 1e-9) & (f < 1 - 1e-9), axis=1))]
        if not front:
            break
    if corners:  # after the passes of this side
        out.append(corners)
    return out


def _corner_passes(surface, layout, z, fp, uv, w, cut, k, alpha, ds):
    """Passes from each corner an untangled swallowtail leaves on the next pass back to the
    bend of this pass ``uv`` it came from (``cut``: [(crossing uv, index of the bend's
    middle in uv)], ``w`` the gaps), where that is farther than ``CORNER_GAPS`` times the
    gap there. The offsets of a pass bent towards them meet at a corner gap / sin(theta / 2)
    from the bend (theta the corner's angle), and the middle between is farther from both
    passes than half a gap: the torus D10 r2 on the sample STEP block left 0.133 mm against
    h_c 0.05 there. As the contour strategy's corner passes (``contour.corner_segments``),
    one along the bisector closes it."""
    out = []
    for c, j in cut:
        c = np.clip(c, 0.0, 1.0)
        q, b = surface.jet(np.array([c[0], uv[j, 0]]), np.array([c[1], uv[j, 1]]), order=0).p
        d = float(np.linalg.norm(q - b))
        if d <= CORNER_GAPS * w[j]:
            continue
        n_pts = max(int(np.ceil(d / ds)), 1) + 1
        f = np.linspace(0.0, 1.0, n_pts)[:, None]
        line = (1 - f) * c + f * uv[j]
        keep = zone_mask(layout.labels, z, line)
        if not fp.whole:
            keep &= fp.contains(line[:, 0], line[:, 1])
        for a, e in runs(keep):
            if e - a < 2:
                continue
            xy = surface.jet(line[a:e, 0], line[a:e, 1], order=0).p[:, :2]
            out.append(Piece(line[a:e], side_of(xy), np.zeros(e - a), z, k + 1, alpha,
                             (False, False)))
    return out


def _smooth(w, size):
    """The widths w along a pass, never wider than any raw width within the window: the
    smallest width within +-window (a torus's widths change fast with the slope: raw, they
    crease the next pass into loops), then its mean over the same window (no steps, and
    still <= every raw width there: each value averaged is a minimum over a window that
    holds the point)."""
    return uniform_filter1d(minimum_filter1d(w, size, mode="nearest"), size, mode="nearest")


def _facing_widths(surface, cutter, h_c, uv, jet, t, b, size, settle, check=3):
    """3-axis spacing from the pass uv towards +b: this pass's +b half-width plus the next
    pass's half-width on its side facing back (``offsets.facing_width``), the next pass's
    frame taken where the spacing puts it (the feed tangent carried over to its tangent
    plane: offsets are locally parallel), ``settle`` times."""
    near = facing_width(surface, cutter, h_c, jet, t, b)
    w = _smooth(near + facing_width(surface, cutter, h_c, jet, t, -b), size)
    for _ in range(settle):
        nxt = march(surface, uv, b, w)
        j2 = surface.jet(nxt[:, 0], nxt[:, 1], order=2)
        n2 = unit_normal(j2, surface.normal_sign)
        t2 = np.gradient(j2.p, axis=0)  # the next pass's own travel direction
        t2 *= np.where(np.einsum("ij,ij->i", t2, t) >= 0, 1.0, -1.0)[:, None]
        t2 -= np.einsum("ij,ij->i", t2, n2)[:, None] * n2
        # where the walk stopped several points at one spot (the domain's edge) the next
        # pass has no direction of its own there: this pass's, in its tangent plane (a
        # zero direction made its curvature 0 / 0 and its width nan)
        still = np.linalg.norm(t2, axis=1) < 1e-9
        t2[still] = t[still] - np.einsum("ij,ij->i", t[still], n2[still])[:, None] * n2[still]
        t2 /= np.maximum(np.linalg.norm(t2, axis=1, keepdims=True), 1e-300)
        b2 = np.cross(n2, t2)
        w = _smooth(near + facing_width(surface, cutter, h_c, j2, t2, -b2), size)
    for _ in range(check):  # narrowed where the two passes' real sweeps leave more than h_c
        cusp = cusp_heights(surface, cutter, uv, march(surface, uv, b, w), b, w)
        over = cusp > h_c
        if not over.any():
            break
        w = _smooth(np.where(over, w * np.sqrt(h_c / np.maximum(cusp, 1e-12)), w), size)
    return w


def zigzag(passes):
    """Pieces in machining order: every other pass reversed (its pieces from far to near)."""
    flat = []
    for r, pieces in enumerate(passes):
        if r % 2:
            pieces = [Piece(pc.uv[::-1], pc.cross[::-1], pc.gap[::-1], pc.zone, pc.pass_k,
                            pc.alpha, pc.edge[::-1]) for pc in pieces[::-1]]
        flat.extend(pieces)
    return flat


class IsoScallop(CurveStrategy):
    name = "isoscallop"
    KEYS = {"master_offset": None, "resample": 0.5}

    def __init__(self, settings=None, key="strategy"):
        super().__init__(settings, key)
        ds = self.settings["resample"]
        if not (isinstance(ds, (int, float)) and ds > 0):
            raise ValueError(f"{key}.resample: expected a positive number of mm, got {ds!r}")

    def check(self, planner, key: str = "strategy") -> None:
        """Also: a ``master_offset`` needs the configured feed direction and must cross the
        part (checked before any plan: a plane off the part holds no master pass)."""
        super().check(planner, key)
        off = self.settings["master_offset"]
        if off is None:
            return
        if isinstance(off, bool) or not isinstance(off, (int, float)):
            raise ValueError(f"{self.key}.master_offset: expected a number of mm, got {off!r}")
        if planner.feed_angle is None:
            raise ValueError(f"{self.key}.master_offset: a master plane needs a fixed "
                             f"feed_angle (the zones' directions are optimized)")
        geom = planner.geometry(np.radians(planner.feed_angle))
        if not geom.d_min <= off <= geom.d_max:
            raise ValueError(f"{self.key}.master_offset: {off:g} mm lies outside the part "
                             f"([{geom.d_min:.3f}, {geom.d_max:.3f}] mm across the feed)")

    def zone_passes(self, planner, layout, z, cutter, lead_tilt):
        return zigzag(zone_passes(planner, layout, z, cutter, planner.h_c, lead_tilt,
                                  self.settings["master_offset"],
                                  float(self.settings["resample"]), key=self.key))
