"""``contour``: concentric loops, inward offsets of the zone's boundary, cut outside in.

The zone's footprint in XY (the whole part: the image of its boundary loops; a zone: the
union of its mesh cells, mapped to XY; on a trimmed face either is cut to the face's
footprint, its holes included) is offset inwards by shapely (GEOS buffers: exact in floating
point, nested by construction, an offset that pinches splits into several loops and one that
vanishes is empty; pyclipr would be faster but works on integer coordinates, and shapely is
already the project's polygon library). The first loop is the boundary itself; the next
offset distance is as far from the current loop as its WORST point allows (the cross-feed
width that leaves h_c, ``offsets.cross_width``, times the horizontal part of the inward
cross-feed), until nothing is left; each part of the offsets ends on its spine (the deepest
offset where that part vanishes, a point or a sliver along its medial axis, cut as a loop
with no scallop measured against it). Each loop is one section, closed, its start moved to
the point nearest the previous loop's end (short links). CC points lie on the surface above
the loops (the XY offsets mapped back to (u, v)). Around a hole the loops are the offsets of
its boundary, outwards into the material. ``link: spiral`` cuts every run of offsets that
stay one loop as one spiral (:func:`spiral`) instead of closed loops linked across.
``corners`` (default true): after the loops, a pass along the bisector of every convex
corner from one loop to the next (:func:`corner_segments`: nested offsets keep sharp
corners, step / sin(theta / 2) apart). Where an offset pinches (between a hole and an
edge), the strips of material neither it nor the last loop before it reaches are cut after
the loops as ridge passes (:func:`ridge_rings`), in one nearest-neighbour tour.
"""

from __future__ import annotations

import numpy as np

from ...geometry.footprint import footprint_of
from ..curves import Piece
from .base import CurveStrategy
from .offsets import cross_width, pass_frame, side_of

__all__ = ["Contour", "zone_polygon", "contour_loops", "ridge_rings", "spiral"]


def zone_polygon(surface, labels, z, n_side: int = 256):
    """The XY polygon of zone z (its mesh cells' union mapped to XY), within the surface's
    trimmed footprint (holes included) where it has one."""
    import shapely

    n, m = labels.shape
    if np.all(labels == z):
        t = np.linspace(0.0, 1.0, n_side, endpoint=False)
        one, zero = np.ones_like(t), np.zeros_like(t)
        rings_uv = [np.column_stack([np.r_[t, one, 1 - t, zero], np.r_[zero, t, one, 1 - t]])]
    else:
        i, j = np.nonzero(labels == z)
        cells = shapely.box(i / n, j / m, (i + 1) / n, (j + 1) / m)
        uni = shapely.unary_union(cells)
        polys = list(getattr(uni, "geoms", [uni]))
        big = max(polys, key=lambda g: g.area)
        ring = shapely.segmentize(big.exterior, 0.25 / max(n, m))
        rings_uv = [np.asarray(ring.coords)[:-1]]
    xy = [surface.jet(r[:, 0], r[:, 1], order=0).p[:, :2] for r in rings_uv]
    poly = shapely.Polygon(xy[0])
    poly = poly if poly.is_valid else shapely.make_valid(poly)
    fp = footprint_of(surface)
    if not fp.whole:
        loops = fp.xy_loops(surface)
        part = shapely.Polygon(loops[0], holes=loops[1:])
        poly = poly.intersection(part if part.is_valid else shapely.make_valid(part))
    return poly


def _to_uv(geom, xy):
    """(u, v) of XY points: the pass tables of feed 0 deg (d = y, s = x) and Newton."""
    d, s = xy[:, 1], xy[:, 0]
    lo, hi = geom.pass_extent(d)
    tau = np.clip((s - lo) / np.where(hi > lo, hi - lo, 1.0), 0.0, 1.0)
    u0, v0 = geom.seed(d, tau)
    return np.column_stack(geom._newton(d, s, u0, v0, iters=8))


#: degrees: a loop turning by more than this at a vertex has a corner (a buffer's rounded
#: arcs turn 11.25 deg a vertex)
CORNER_DEG = 30.0


def _corners(ring, min_turn_deg: float = CORNER_DEG) -> np.ndarray:
    """The convex corners (XY, (K, 2)) of a closed ring: vertices where it turns towards
    its inside by more than ``min_turn_deg``."""
    import shapely

    xy = np.asarray(ring.coords)[:-1]
    if len(xy) < 3:
        return np.zeros((0, 2))
    if not shapely.LinearRing(xy).is_ccw:
        xy = xy[::-1]
    e_in, e_out = xy - np.roll(xy, 1, axis=0), np.roll(xy, -1, axis=0) - xy
    cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
    turn = np.degrees(np.arctan2(cross, np.sum(e_in * e_out, axis=1)))  # > 0: left (convex)
    return xy[turn > min_turn_deg]


def corner_segments(rings, steps, ds: float = 0.5, region=None):
    """Corner passes: XY polylines from every convex corner of each outer loop to the nearest
    point of the next loops inwards, where that is farther than the loops' spacing (``rings``
    per offset distance, (ring, outer) each; ``steps`` the spacing to the next). Within
    ``region`` (the zone's polygon) a pass keeps its points up to the first one outside it
    (across a hole or a notch the nearest loop point may lie beyond it). An inward offset keeps a
    polygon's convex corners sharp, so nested loops that are ``step`` apart along their
    edges are step / sin(theta / 2) apart at a corner of interior angle theta (step sqrt 2
    at a square's): halfway along the bisector the nearest loop is 0.586 step away on a
    square's, 17 % over the 0.5 step between straight loops, and a cusp ~ width^2 stands 37 %
    higher (measured: 0.367 mm on Choi's surface, ball, h_c 0.254, on the diagonals). A pass
    along the bisector from each corner to the next loop leaves every point of the corner
    within half a step of a pass."""
    import shapely

    out = []
    for k in range(len(rings) - 1):
        nxt = shapely.MultiLineString([list(r.coords) for r, _ in rings[k + 1]]) \
            if rings[k + 1] else None
        if nxt is None:
            continue
        for ring in (r for r, outer in rings[k] if outer):
            for c in _corners(ring):
                pt = shapely.Point(c)
                q = nxt.interpolate(nxt.project(pt))
                end = np.array([q.x, q.y])
                if np.linalg.norm(end - c) <= 1.05 * steps[k]:
                    continue  # the next loop is as close as along the edges: no corner left
                n_pts = max(int(np.ceil(np.linalg.norm(end - c) / ds)), 1) + 1
                f = np.linspace(0.0, 1.0, n_pts)[:, None]
                xy = (1 - f) * c + f * end
                if region is not None:
                    inside = shapely.covers(region, shapely.points(xy))
                    xy = xy[:len(xy) if inside.all() else int(np.argmin(inside))]
                if len(xy) >= 2:
                    out.append((k, xy))
    return out


def ridge_rings(here, there, step, lost=(), corners=None) -> list:
    """Polygons of the material between the offsets ``here`` and ``there`` (``step`` further
    in) that neither covers: farther than step / 2 from ``here``'s boundary and from
    ``there``. Where the offsets nest that is nothing; where an offset pinches (a part of
    the face between a hole and an edge, the fronts from both sides meet on its medial
    axis) the next offset has left the ridge, and the last loop reaches it from both sides
    only within step / 2: a sliver along the ridge stays high (the sample STEP block's ball
    plan: 0.08-0.14 mm against h_c 0.05 on the ridge between its hole and its edges).
    Slivers thinner than a tenth of the step (at most 1 % over h_c at their middle), those
    within a step of one of ``corners`` (XY, (K, 2): the gap inside a loop's convex corner,
    which its corner pass cuts, :func:`corner_segments`) and the parts ``lost`` (each gets
    its spine) are left out; each sliver's boundary, cut as a loop (its two long sides lie
    within step / 2 of its middle), covers it."""
    import shapely

    half = 0.5 * step * (1.0 + 1e-3)
    reach = shapely.union(shapely.boundary(here).buffer(half), there.buffer(half))
    eps = 0.05 * step
    left = here.difference(reach).buffer(-eps).buffer(eps)
    if left.is_empty:
        return []
    near = shapely.MultiPoint(corners).buffer(step) if corners is not None and len(corners) \
        else None
    return [g for g in _polygons(left.intersection(here))
            if not any(g.intersects(p) for p in lost) and not (near and g.intersects(near))]


def _tour(pieces, surface):
    """The closed ``pieces`` reordered as a greedy nearest-neighbour tour in XY from the
    first one's start, each started at its point nearest the previous one's end."""
    left = list(pieces)
    xy = [surface.jet(pc.uv[:, 0], pc.uv[:, 1], order=0).p[:, :2] for pc in left]
    out, here = [], xy[0][0] if xy else None
    while left:
        d = [np.linalg.norm(p - here, axis=1) for p in xy]
        k = int(np.argmin([x.min() for x in d]))
        pc, p, j = left.pop(k), xy.pop(k), int(np.argmin(d[k]))
        if j:  # a closed ring (last point = first): start it at j
            ring = np.r_[np.arange(j, len(pc.uv) - 1), np.arange(0, j + 1)]
            pc = Piece(pc.uv[ring], pc.cross[ring], pc.gap[ring], pc.zone, pc.pass_k, pc.alpha)
        out.append(pc)
        here = p[j]  # a closed ring ends where it starts
    return out


def _reach_of(reach):
    """(tree over the loop points, their half-widths) of ``reach`` ([(xy (m, 2), half-width
    (m,))] per ring of a level: half the spacing that leaves h_c there), or None."""
    if not reach:
        return None
    from scipy.spatial import cKDTree

    return (cKDTree(np.concatenate([r[0] for r in reach])),
            np.concatenate([r[1] for r in reach]))


def _beyond_reach(gap, reach, margin: float = 1.02) -> bool:
    """Whether some vertex of the ``gap`` polygon lies farther from its nearest loop point
    than ``margin`` times that point's own reach (``reach``: :func:`_reach_of`). The offsets
    are spaced by their worst point, so most of a loop reaches beyond half the step; a gap
    that every loop point beside it reaches is no gap."""
    if reach is None:
        return True
    tree, half = reach
    d, j = tree.query(np.asarray(gap.exterior.coords))
    return bool(np.any(d > margin * half[j]))


def _polygons(region, degenerate: bool = False) -> list:
    """The polygons of an offset region; ``degenerate``: also those of (nearly) no area (an
    offset at the distance where it vanishes is a point or a sliver along the medial axis)."""
    return [g for g in getattr(region, "geoms", [region])
            if g.geom_type == "Polygon" and not g.is_empty and (degenerate or g.area > 1e-9)]


def contour_loops(planner, layout, z, cutter, h_c, lead_tilt=None, ds=0.5, max_loops=2000,
                  corners=None, ridges=None):
    """[[Piece]] per offset distance (outside in) of zone z. ``corners``: a list that
    receives the corner passes (:func:`corner_segments`) as pieces (gap 0: no scallop
    measured against them); ``ridges``: one that receives the index of the level that
    holds the ridge passes (:func:`ridge_rings`: one tour after the loops).

    Every part of the offsets gets a spine: where a part vanishes before the next offset
    distance (the whole zone at the end, or one part of an offset that split, earlier), the
    deepest offset of that part (a point or a sliver along its medial axis) is cut too, so
    the middle between its last loop and its spine is not left standing."""
    import shapely

    surface = planner.surface
    geom = planner.geometry(0.0)
    poly = zone_polygon(surface, layout.labels, z)
    out, dist, prev, end, last_region, reach, last_reach = [], 0.0, None, None, None, [], []
    found_rings: list = []
    all_rings, all_steps = [], []
    last_parts: list = []

    def pieces_of(rings):
        """(pieces, steps) of closed rings: each its (u, v) above the XY ring, the inward
        cross-feed, gap 0 (a loop's is set once its step is known), and the step to the next
        offset its worst point allows."""
        nonlocal end, reach
        pieces, steps, reach = [], [], []
        for ring, outer in rings:
            xy = np.asarray(shapely.segmentize(ring, ds).coords)[:-1]
            if len(xy) < 3:
                continue
            if shapely.LinearRing(xy).is_ccw is not outer:
                xy = xy[::-1]
            if end is not None:  # start where the previous loop ended
                xy = np.roll(xy, -int(np.argmin(np.linalg.norm(xy - end, axis=1))), axis=0)
            xy = np.vstack([xy, xy[:1]])
            uv = _to_uv(geom, xy)
            jet, n, t, b = pass_frame(surface, uv)
            tan_xy = np.gradient(xy, axis=0)
            inward = np.column_stack([-tan_xy[:, 1], tan_xy[:, 0]])  # left of a ccw loop
            inward /= np.maximum(np.linalg.norm(inward, axis=1, keepdims=True), 1e-300)
            b *= np.where(np.sum(b[:, :2] * inward, axis=1) >= 0, 1.0, -1.0)[:, None]
            w = cross_width(surface, cutter, h_c, jet, t, b, lead_tilt)
            horiz = np.abs(np.sum(b[:, :2] * inward, axis=1))
            steps.append(float(np.min(w * horiz)))
            reach.append((xy, 0.5 * w * horiz))
            cross = np.column_stack([inward, np.zeros(len(xy))])
            pieces.append(Piece(uv, cross, np.zeros(len(uv)), z, len(out), layout.alpha[z]))
            end = xy[-1]
        return pieces, steps

    def deepest(part, whole):
        """The zone's offset at the largest distance in [prev, dist) where ``part`` (one
        polygon of the offset at prev) still has material (bisection); ``whole``: the part is
        all that is left of the zone."""
        def left(m):
            region = poly.buffer(-m)
            return region if whole else region.intersection(part)

        lo, hi = prev, dist
        for _ in range(20):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if not left(mid).is_empty else (lo, mid)
        return left(lo)

    def rings_of(polys):
        # outer boundaries counter-clockwise, holes clockwise: the material on the left
        return [(g.exterior, True) for g in polys] + [(h, False) for g in polys for h in g.interiors]

    for _ in range(max_loops):
        region = poly if dist == 0 else poly.buffer(-dist)
        spine = region.is_empty and prev is not None
        if spine:  # nothing left at the next distance: the zone's last spines, then stop
            lost = last_parts
        else:
            if region.is_empty:
                break
            lost = [g for g in last_parts if not region.intersects(g)]
        spines, spine_rings, spine_steps = [], [], []
        for part in lost:  # parts gone before this distance: each one's deepest offset
            deep_rings = rings_of(_polygons(deepest(part, spine and len(lost) == 1), degenerate=True))
            pieces, steps = pieces_of(deep_rings)
            spines += pieces
            spine_rings += deep_rings
            spine_steps += steps
        if spines:
            out.append(spines)
        if spine:
            if spines:  # the corner passes of the last loops run to the spines
                all_rings.append(spine_rings)
                all_steps.append(max(min(spine_steps), 1e-3))
            break
        polys = _polygons(region)
        rings = rings_of(polys)
        pieces, steps = pieces_of(rings)
        if not pieces:
            break
        loop_reach = reach
        if ridges is not None and prev is not None:  # cut after the loops (one tour)
            keep = end  # the loops' own links stay as they were
            # the gaps inside the loops' convex corners are the corner passes' (or left, as
            # configured): not ridges
            served = np.concatenate([_corners(r) for r, outer in rings_of(last_parts) if outer]
                                    + [np.zeros((0, 2))])
            gaps = ridge_rings(last_region, region, dist - prev, lost, served)
            if gaps:  # the two levels' loop points, searched once for all the gaps
                here, there = _reach_of(last_reach), _reach_of(loop_reach)
                gaps = [g for g in gaps if _beyond_reach(g, here) and _beyond_reach(g, there)]
            found_rings += rings_of(gaps)
            end = keep
        step = max(min(steps), 1e-3)
        for pc in pieces:  # a loop's gap: the step to the next offset
            pc.gap[:] = step
        all_rings.append(rings)
        all_steps.append(step)
        out.append(pieces)
        last_parts, last_region, last_reach = polys, region, loop_reach
        prev, dist = dist, dist + step
    if found_rings:  # after the loops, one greedy nearest-neighbour tour (started from the
        # last loop's end it was 13.5 mm longer on the sample STEP block's ball plan)
        ridges.append(len(out))
        out.append(_tour(pieces_of(found_rings)[0], surface))
    if corners is not None:
        for k, xy in corner_segments(all_rings, all_steps, ds, region=poly):
            corners.append(Piece(_to_uv(geom, xy), side_of(xy),
                                 np.zeros(len(xy)), z, len(out) + len(corners),
                                 layout.alpha[z]))
    return out


def spiral(loops):
    """The nested loops of one offset chain (each a single closed :class:`Piece`, outside
    in, each starting at the point nearest the previous one's end) as ONE piece: the outer
    loop whole, then from each loop to the next the blend (1 - tau) loop_k(tau) +
    tau loop_k+1(tau) over the loops' normalized arc length tau (in (u, v); both start at
    tau = 0 and close at tau = 1, so each blend ends where the next begins), then the inner
    loop whole. The tool never leaves the surface between loops; the distance between
    turns is a blend of the loops' own spacings."""
    def at(pc, tau):
        d = np.linalg.norm(np.diff(pc.uv, axis=0), axis=1)
        arc = np.r_[0.0, np.cumsum(d)]
        arc /= max(arc[-1], 1e-300)
        return (np.column_stack([np.interp(tau, arc, pc.uv[:, k]) for k in range(2)]),
                np.column_stack([np.interp(tau, arc, pc.cross[:, k]) for k in range(3)]),
                np.interp(tau, arc, pc.gap))

    first, last = loops[0], loops[-1]
    uv, cross, gap = [first.uv], [first.cross], [first.gap]
    for a, b in zip(loops[:-1], loops[1:]):
        tau = np.linspace(0.0, 1.0, max(len(a.uv), len(b.uv)))[1:]
        (ua, ca, ga), (ub, cb, gb) = at(a, tau), at(b, tau)
        uv.append((1 - tau)[:, None] * ua + tau[:, None] * ub)
        cross.append((1 - tau)[:, None] * ca + tau[:, None] * cb)
        gap.append((1 - tau) * ga + tau * gb)
    uv.append(last.uv[1:])
    cross.append(last.cross[1:])
    gap.append(last.gap[1:])
    return Piece(np.concatenate(uv), np.concatenate(cross), np.concatenate(gap), first.zone,
                 first.pass_k, first.alpha)


class Contour(CurveStrategy):
    name = "contour"
    KEYS = {"resample": 0.5, "link": "loops", "corners": True}

    def __init__(self, settings=None, key="strategy"):
        super().__init__(settings, key)
        if self.settings["link"] not in ("loops", "spiral"):
            raise ValueError(f"{key}.link: expected loops or spiral, got "
                             f"{self.settings['link']!r}")
        if not isinstance(self.settings["corners"], bool):
            raise ValueError(f"{key}.corners: expected true or false, got "
                             f"{self.settings['corners']!r}")

    def zone_passes(self, planner, layout, z, cutter, lead_tilt):
        # then the corner passes, after the loops (corner_segments; corners: false, none)
        corners, ridges = [], []
        loops = contour_loops(planner, layout, z, cutter, planner.h_c, lead_tilt,
                              float(self.settings["resample"]),
                              corners=corners if self.settings["corners"] else None,
                              ridges=ridges)
        if self.settings["link"] == "loops":
            # every loop the same way round
            return [pc for pieces in loops for pc in pieces] + corners
        out, chain = [], []
        for k, pieces in enumerate(loops):  # a spiral through every run of offsets that
            if len(pieces) == 1 and k not in ridges:  # stay one loop
                chain.append(pieces[0])
                continue
            if chain:
                out.append(spiral(chain))
                chain = []
            out.extend(pieces)
        if chain:
            out.append(spiral(chain))
        return out + corners
