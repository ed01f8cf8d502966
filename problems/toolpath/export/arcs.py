"""Tolerance-based reduction of a polyline into NC blocks: merged lines and fitted arcs.

A run of cutting moves at one feed is a polyline ``P_0 .. P_n`` (the control interpolates
linearly between its points). Written as fewer blocks, it stays within the chord tolerance
``tol`` of that polyline:

- **lines**: ``P_i .. P_j`` becomes one ``G1`` when every point between lies within ``tol``
  of the segment ``P_i P_j`` (the distance to the segment, not to its line, so a reversal is
  never merged away);
- **arcs** (a dialect that declares them): ``P_i .. P_j`` (at least three segments) becomes
  one ``G2`` / ``G3`` in the plane ``G17`` (XY), ``G18`` (ZX) or ``G19`` (YZ) whose normal
  coordinate is the same at every point, on the circle through ``P_i``, ``P_m`` and ``P_j``
  (``m`` the middle index), when the points advance the same way round it, turn by at most
  ``max_sweep`` in all, and for every segment ``P_k P_k+1`` the arc's sagitta over it plus
  the larger radial error of its two points is at most ``tol``. Then every point of the
  polyline lies within ``tol`` of the arc and every point of the arc within ``tol`` of the
  polyline (the arc between ``P_k`` and ``P_k+1`` is within its sagitta of their chord, and
  the chord's ends are within their radial errors of the circle).

At each block start the longest line and the longest arc are searched (doubling, then
bisection on the end index, each candidate checked in full), and the one that reaches
further is written (compiled with numba: the search is sequential, block after block, which
numpy cannot vectorize). ``arc_points`` turns an arc block back into points within a chord
tolerance (the G-code readers use it).

The plane table, G2 / G3 (clockwise / counter-clockwise seen from the plane's positive
normal axis) and the centre words ``I J K`` (incremental from the arc's start) are those of
ISO 6983.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

PLANES = {"17": (0, 1, 2), "18": (2, 0, 1), "19": (1, 2, 0)}  # (first, second, normal) axes
PLANAR_EPS = 1e-7  # mm: the normal coordinate counts as constant within this
MIN_ARC_SEGMENTS = 3
MAX_RADIUS = 1e4  # mm: flatter than this, the points are written as lines


@dataclass
class Blocks:
    """A polyline ``P`` (n + 1, 3) as blocks: block k moves from the previous block's end
    (``P_0`` for the first) to ``P[end[k]]``; ``motion[k]`` 1 (line), 2 (G2) or 3 (G3);
    ``plane[k]`` "17" / "18" / "19" for an arc ("" for a line); ``centre[k]`` (3,) the arc's
    centre (NaN for a line; its normal coordinate is the plane's)."""

    end: np.ndarray
    motion: np.ndarray
    plane: list[str]
    centre: np.ndarray


def segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each of ``points`` (k, 3) to the segment from ``a`` to ``b``."""
    ab = b - a
    ln2 = float(ab @ ab)
    w = points - a
    t = np.clip(w @ ab / ln2, 0.0, 1.0) if ln2 > 0 else np.zeros(len(points))
    return np.linalg.norm(w - t[:, None] * ab, axis=1)


def circle_through(p0, p1, p2):
    """(centre (2,), radius) of the circle through three 2-D points; None when they are
    (nearly) collinear."""
    out = _circle(np.asarray(p0, float), np.asarray(p1, float), np.asarray(p2, float))
    return None if out[2] < 0 else (np.array(out[:2]), float(out[2]))


@numba.njit(cache=True)
def _circle(p0, p1, p2):  # pragma: no cover - compiled
    bx, by, cx, cy = p1[0] - p0[0], p1[1] - p0[1], p2[0] - p0[0], p2[1] - p0[1]
    d = 2.0 * (bx * cy - by * cx)
    bb, cc = bx * bx + by * by, cx * cx + cy * cy
    scale = max(bb, cc)
    if scale == 0.0 or abs(d) <= 1e-12 * scale:
        return 0.0, 0.0, -1.0
    ux, uy = (cy * bb - by * cc) / d, (bx * cc - cx * bb) / d
    return p0[0] + ux, p0[1] + uy, math.hypot(ux, uy)


@numba.njit(cache=True)
def _line_ok(P, i, j, tol):  # pragma: no cover - compiled
    """Every point strictly between i and j within tol of the segment P_i P_j."""
    ab = P[j] - P[i]
    ln2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]
    for k in range(i + 1, j):
        w = P[k] - P[i]
        t = 0.0
        if ln2 > 0.0:
            t = min(1.0, max(0.0, (w[0] * ab[0] + w[1] * ab[1] + w[2] * ab[2]) / ln2))
        dx, dy, dz = w[0] - t * ab[0], w[1] - t * ab[1], w[2] - t * ab[2]
        if dx * dx + dy * dy + dz * dz > tol * tol:
            return False
    return True


@numba.njit(cache=True)
def _arc_fit(P, i, j, a, b, c, tol, max_sweep, max_radius, out):  # pragma: no cover - compiled
    """The arc through P[i..j] in the plane (a, b) with normal axis c (module docstring):
    its motion 2 (clockwise) or 3, the centre in ``out`` (3,); 0 when it does not fit."""
    for k in range(i + 1, j + 1):
        if abs(P[k, c] - P[i, c]) > PLANAR_EPS:
            return 0
    m = i + (j - i) // 2
    q0 = np.array([P[i, a], P[i, b]])
    q1 = np.array([P[m, a], P[m, b]])
    q2 = np.array([P[j, a], P[j, b]])
    ox, oy, r = _circle(q0, q1, q2)
    if r < 0.0 or r > max_radius:
        return 0
    sign = 0.0
    sweep = 0.0
    ux, uy = P[i, a] - ox, P[i, b] - oy
    e_prev = abs(math.hypot(ux, uy) - r)
    for k in range(i + 1, j + 1):
        vx, vy = P[k, a] - ox, P[k, b] - oy
        step = math.atan2(ux * vy - uy * vx, ux * vx + uy * vy)
        if sign == 0.0:
            sign = 1.0 if step > 0.0 else -1.0
        step *= sign
        if step <= 0.0 or step >= 0.5 * math.pi:
            return 0
        sweep += step
        if sweep > max_sweep:
            return 0
        e = abs(math.hypot(vx, vy) - r)
        if r * (1.0 - math.cos(0.5 * step)) + max(e, e_prev) > tol:
            return 0
        ux, uy, e_prev = vx, vy, e
    out[a], out[b], out[c] = ox, oy, P[i, c]
    return 3 if sign > 0.0 else 2


@numba.njit(cache=True)
def _ok(P, i, j, plane, tol, max_sweep, max_radius, out):  # pragma: no cover - compiled
    """Line (plane < 0) or arc in plane 0 / 1 / 2 (G17 / G18 / G19) from P_i to P_j."""
    if plane < 0:
        return 1 if _line_ok(P, i, j, tol) else 0
    if plane == 0:
        return _arc_fit(P, i, j, 0, 1, 2, tol, max_sweep, max_radius, out)
    if plane == 1:
        return _arc_fit(P, i, j, 2, 0, 1, tol, max_sweep, max_radius, out)
    return _arc_fit(P, i, j, 1, 2, 0, tol, max_sweep, max_radius, out)


@numba.njit(cache=True)
def _longest(P, i, last, first, plane, tol, max_sweep, max_radius, out):  # pragma: no cover
    """The largest j in [first, last] that fits, by doubling then bisection on j (every
    candidate checked in full); -1 if ``first`` does not fit."""
    if first > last or _ok(P, i, first, plane, tol, max_sweep, max_radius, out) == 0:
        return -1
    good, k = first, 2 * (first - i)
    while i + k <= last and _ok(P, i, i + k, plane, tol, max_sweep, max_radius, out) != 0:
        good, k = i + k, 2 * k
    bad = min(i + k, last + 1)
    while bad - good > 1:
        mid = (good + bad) // 2
        if _ok(P, i, mid, plane, tol, max_sweep, max_radius, out) != 0:
            good = mid
        else:
            bad = mid
    return good


@numba.njit(cache=True)
def _fit(P, tol, arcs, use_plane, max_sweep, max_radius, min_segments):  # pragma: no cover - compiled
    n = P.shape[0]
    last = n - 1
    ends = np.empty(n, np.int64)
    motion = np.empty(n, np.int8)
    plane = np.full(n, -1, np.int8)
    centre = np.full((n, 3), np.nan)
    out = np.empty(3)
    normal = (2, 1, 0)
    count, i = 0, 0
    while i < last:
        j_line = _longest(P, i, last, i + 1, -1, tol, max_sweep, max_radius, out)
        best_plane, j_arc = -1, -1
        if arcs and i + min_segments <= last:
            for p in range(3):
                c = normal[p]
                if use_plane[p] and abs(P[i + 1, c] - P[i, c]) <= PLANAR_EPS \
                        and abs(P[i + 2, c] - P[i, c]) <= PLANAR_EPS:
                    best_plane = p
                    break
            if best_plane >= 0:
                j_arc = _longest(P, i, last, i + min_segments, best_plane, tol, max_sweep, max_radius, out)
        if j_arc > j_line:
            motion[count] = _ok(P, i, j_arc, best_plane, tol, max_sweep, max_radius, out)
            plane[count] = best_plane
            centre[count] = out
            ends[count] = j_arc
            i = j_arc
        else:
            motion[count] = 1
            ends[count] = j_line
            i = j_line
        count += 1
    return ends[:count], motion[:count], plane[:count], centre[:count]


PLANE_NAMES = ("17", "18", "19")


def fit_blocks(points: np.ndarray, tol: float, arcs: bool = True, planes=PLANE_NAMES,
               max_sweep: float = math.pi) -> Blocks:
    """The blocks of the polyline ``points`` (n + 1, 3) within ``tol`` (module docstring);
    ``arcs`` False: lines only; ``planes``: the arc planes allowed."""
    P = np.ascontiguousarray(points, dtype=float)
    if len(P) < 2:
        return Blocks(np.zeros(0, int), np.zeros(0, np.int8), [], np.zeros((0, 3)))
    if not tol > 0:
        raise ValueError(f"tolerance: expected > 0, got {tol!r}")
    use = np.array([p in planes for p in PLANE_NAMES])
    ends, motion, plane, centre = _fit(P, float(tol), bool(arcs), use, float(max_sweep), MAX_RADIUS,
                                       MIN_ARC_SEGMENTS)
    return Blocks(ends.astype(int), motion, [PLANE_NAMES[k] if k >= 0 else "" for k in plane], centre)


@dataclass
class Reduced:
    """A program's moves after reduction: ``keep`` (m,) the points written; for each,
    ``motion`` 0 (rapid), 1 (line), 2 / 3 (G2 / G3), ``plane`` and ``centre`` (arcs)."""

    keep: np.ndarray
    motion: np.ndarray
    plane: list[str]
    centre: np.ndarray


def reduce_moves(tip: np.ndarray, rapid: np.ndarray, feed: np.ndarray, tol: float, arcs: bool) -> Reduced:
    """Every run of cutting moves at one feed (``rapid`` False, ``feed`` equal; a plunge is
    its own run) reduced by :func:`fit_blocks` from the point before it; rapids are kept."""
    tip = np.asarray(tip, float)
    m = len(tip)
    keep = np.ones(m, bool)
    motion = np.where(rapid, 0, 1).astype(np.int8)
    plane = [""] * m
    centre = np.full((m, 3), np.nan)
    cut = ~np.asarray(rapid, bool)
    f = np.nan_to_num(np.asarray(feed, float), nan=-1.0)
    brk = np.r_[True, (cut[1:] != cut[:-1]) | (f[1:] != f[:-1])]
    starts = np.flatnonzero(brk)
    for s, e in zip(starts, np.r_[starts[1:], m]):
        if not cut[s] or e - s < 2:
            continue
        base = max(s - 1, 0)
        blocks = fit_blocks(tip[base:e], tol, arcs)
        keep[s:e] = False
        keep[base] = True  # the run's start (the point before it, or its own first point)
        idx = base + blocks.end
        keep[idx] = True
        motion[idx] = blocks.motion
        centre[idx] = blocks.centre
        for k, n in enumerate(idx):
            plane[n] = blocks.plane[k]
    return Reduced(keep, motion, plane, centre)


def arc_points(start, end, centre, plane: str, clockwise: bool, tol: float) -> np.ndarray:
    """Points (k, 3) strictly inside the arc from ``start`` to ``end`` about ``centre`` (in
    ``plane``, the normal coordinate interpolated linearly: a helix) no chord of which is
    further than ``tol`` from the arc; a full circle when ``start`` and ``end`` coincide."""
    a, b, c = PLANES[plane]
    p0, p1, q = (np.array([p[a], p[b]], float) for p in (start, end, centre))
    r = float(np.hypot(*(p0 - q)))
    t0 = math.atan2(*(p0 - q)[::-1])
    t1 = math.atan2(*(p1 - q)[::-1])
    sweep = (t0 - t1) % (2 * math.pi) if clockwise else (t1 - t0) % (2 * math.pi)
    if sweep < 1e-12:
        sweep = 2 * math.pi
    step = 2 * math.acos(max(-1.0, 1 - tol / r)) if tol < r else math.pi / 2
    k = max(1, int(math.ceil(sweep / step - 1e-12)))
    t = t0 + (-1 if clockwise else 1) * sweep * np.arange(1, k) / k
    out = np.empty((k - 1, 3))
    out[:, a], out[:, b] = q[0] + r * np.cos(t), q[1] + r * np.sin(t)
    out[:, c] = start[c] + (end[c] - start[c]) * np.arange(1, k) / k
    return out
