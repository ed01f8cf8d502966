"""Cell areas clipped to the part: a cell that straddles the footprint's edge weighs only
the part of it that lies on the part.

The simulation grid's cells are squares of side h over XY; a cell is simulated when its
centre lies over the part (``design.py``). Weighting every such cell by its whole area
(h^2 / n_z) counts the strip of each edge cell that hangs past the part, and drops the
sliver of part inside a cell whose centre lies just outside. Here:

1. the footprint is the XY image of the surface's boundary loops (``surface.footprint``
   when the surface has one, else the unit square's boundary), a shapely polygon;
2. each cell the boundary may cross (a cell within one cell of a change of ``inside``, or
   one the boundary polyline passes through) gets the fraction of its square inside the
   polygon (shapely intersection areas); every other cell is wholly on or off the part;
3. the part inside a cell whose centre is off the part (it holds no residual) goes to its
   simulated neighbour (edge neighbours first, then corners): its figures stand for it;
4. area = fraction x h^2 / n_z (n_z of the cell that carries it).

So the clipped areas add up to the footprint polygon's area over n_z: exact on a plane
(tested within 1e-6 relative), and the midpoint rule's area elsewhere.

shapely (GEOS) is used for the polygon clipping: vectorized over arrays of cell boxes,
exact in floating point, and already a dependency of the project.
"""

from __future__ import annotations

import numpy as np

__all__ = ["footprint_polygon", "clipped_fractions"]

_NEIGHBOURS = ((0, 1), (0, -1), (1, 0), (-1, 0), (1, 1), (1, -1), (-1, 1), (-1, -1))


def _boundary_loops_uv(surface, n: int) -> list[np.ndarray]:
    """The boundary loops of the surface's domain in (u, v): ``surface.footprint.loops``
    when it has them, else the unit square's boundary, n points a side."""
    fp = getattr(surface, "footprint", None)
    loops = getattr(fp, "loops", None) if fp is not None else None
    if loops:  # densified: a straight (u, v) edge is curved in XY
        if hasattr(fp, "dense"):  # as the footprint knows it (a CAD face's: as sampled)
            return fp.dense(1.0 / n)
        return [_densify(np.asarray(lp, float), 1.0 / n) for lp in loops]
    t = np.linspace(0.0, 1.0, n, endpoint=False)
    one, zero = np.ones_like(t), np.zeros_like(t)
    return [np.column_stack([np.concatenate([t, one, 1 - t, zero]),
                             np.concatenate([zero, t, one, 1 - t])])]


def _densify(loop, step):
    """The closed (u, v) polyline ``loop`` with points at most ``step`` apart."""
    nxt = np.roll(loop, -1, axis=0)
    k = np.maximum(np.ceil(np.linalg.norm(nxt - loop, axis=1) / step).astype(int), 1)
    f = np.concatenate([np.arange(m) / m for m in k])
    owner = np.repeat(np.arange(len(loop)), k)
    return loop[owner] + f[:, None] * (nxt[owner] - loop[owner])


def footprint_polygon(surface, n: int = 1024):
    """The part's XY footprint as a shapely (Multi)Polygon: the outer loop minus the holes
    (every loop after the first is a hole)."""
    import shapely

    rings = []
    for lp in _boundary_loops_uv(surface, n):
        p = surface.jet(lp[:, 0], lp[:, 1], order=0).p
        rings.append(p[:, :2])
    poly = shapely.Polygon(rings[0], holes=rings[1:] or None)
    return shapely.make_valid(poly) if not poly.is_valid else poly


def clipped_fractions(polygon, x0: float, y0: float, h: float, inside: np.ndarray
                      ) -> tuple[np.ndarray, float]:
    """(weight, lost): per cell (ny, nx) the share of a cell's square h^2 of part it carries
    (its own part inside the polygon plus the slivers it takes from neighbours whose centre
    is off the part), and the area (mm^2 in XY) of slivers no simulated neighbour could take."""
    import shapely

    ny, nx = inside.shape
    frac = inside.astype(float)
    # candidates: cells next to a change of inside, and cells the boundary passes through
    cand = np.zeros_like(inside)
    pad = np.pad(inside, 1, mode="constant")
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            cand |= pad[1 + dy:1 + dy + ny, 1 + dx:1 + dx + nx] != inside
    bound = shapely.get_coordinates(shapely.boundary(polygon))
    if len(bound) > 1:  # densify: at most h / 4 between boundary samples
        seg = np.linalg.norm(np.diff(bound, axis=0), axis=1)
        k = np.maximum(np.ceil(seg / (0.25 * h)).astype(int), 1)
        owner = np.repeat(np.arange(len(seg)), k)
        f = (np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)) / np.repeat(k, k)
        pts = bound[owner] + f[:, None] * (bound[owner + 1] - bound[owner])
        ix = np.rint((pts[:, 0] - x0) / h).astype(int)
        iy = np.rint((pts[:, 1] - y0) / h).astype(int)
        ok = (ix >= 0) & (ix < nx) & (iy >= 0) & (iy < ny)
        cand[iy[ok], ix[ok]] = True
    cy, cx = np.nonzero(cand)
    cxs, cys = x0 + cx * h, y0 + cy * h
    boxes = shapely.box(cxs - 0.5 * h, cys - 0.5 * h, cxs + 0.5 * h, cys + 0.5 * h)
    shapely.prepare(polygon)
    part = shapely.area(shapely.intersection(boxes, polygon)) / (h * h)
    frac[cy, cx] = np.clip(part, 0.0, 1.0)
    weight = np.where(inside, frac, 0.0)
    lost = 0.0
    orphan = ~inside[cy, cx] & (frac[cy, cx] > 0)
    for y, x in zip(cy[orphan], cx[orphan]):
        for dy, dx in _NEIGHBOURS:
            j, i = y + dy, x + dx
            if 0 <= j < ny and 0 <= i < nx and inside[j, i]:
                weight[j, i] += frac[y, x]
                break
        else:
            lost += frac[y, x] * h * h
    return weight, lost
