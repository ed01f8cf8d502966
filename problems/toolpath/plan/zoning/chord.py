"""Chord tolerance of a section's CL points: split the straight moves until each stays
within a tolerance of the CL curve it stands for.

The machine joins consecutive CL points of a section by a straight move of the tool tip.
The CL curve those points sample is the placement's tip as the CC point runs along the
section: for the drop-cutter placement, the gouge-free tip z at every XY of the plane.
Where that curve bends (near a part edge or a ridge the drop-cutter tip falls away along
the cutter's profile) the chord leaves it: below a convex stretch the tool cuts into the
part between two gouge-free CL points. This is the CL analogue of the CC chord error that
``plan/points.py`` bounds along the sections (Fountas et al.: cut tolerance 0.01 mm);
``Planner.cl_path`` applies it to 3-axis plans.

Measure: for a move from tip P_i to tip P_{i+1}, the placed tip at the CC point of XY
(1 - q) xy_i + q xy_{i+1} against the chord point (1 - q) P_i + q P_{i+1}, for q = 1/4,
1/2, 3/4 (the plane's points are linear in XY, so these are the section's points at the
quarter and mid parameters); the move's deviation is the largest 3D distance. For the
drop placement the tips share the chord's XY, so this is the vertical gap, which bounds
the depth the move cuts below (or leaves above) the gouge-free tip there.

Rounds: every move above the tolerance gets its mid-point as a new CL point (its CC point
and tip are the ones just computed), all moves of a round at once; only the two halves are
checked in the next round. The loop ends when no move is above the tolerance, or after
``rounds`` rounds (a jump of the tip, which splitting never closes, stops there),
or where the mid-point's XY is off the footprint (no CC point to place).
"""

from __future__ import annotations

import numpy as np

from ...cutters.surface_grid import uv_at_xy
from ...geometry.surface import unit_normal

__all__ = ["refine_moves", "refine_chords", "refine_drop_moves", "split_moves"]

_Q = np.array([0.25, 0.5, 0.75])


def _placed(surface, cutter, place, xy, uv0):
    """(ok, uv, cc, normal, tip) of the CC points at XY (k, 2); nan tips where ``xy`` is off
    the footprint."""
    uv, ok = uv_at_xy(surface, xy, uv0)
    jet = surface.jet(uv[:, 0], uv[:, 1], order=1)
    cc, normal = jet.p, unit_normal(jet, surface.normal_sign)
    tip = np.full((len(xy), 3), np.nan)
    if ok.any():
        tip[ok] = place(cutter, surface, cc[ok], normal[ok])
    return ok, uv, cc, normal, tip


def split_moves(points: dict, move_dev, left, new: dict):
    """Insert a row after each row index of ``left`` (the moves being split): the fields of
    ``new``, the other fields repeated from the left neighbour, ``inserted`` (when the points
    carry it) True. Returns (points, move deviations with 0 for the new halves, pending: the
    moves to check next round, both halves of every split)."""
    pts = dict(points)
    new = dict(new)
    if "inserted" in pts:
        new["inserted"] = np.ones(len(left), bool)
    for key, arr in pts.items():
        pts[key] = np.insert(arr, left + 1, new[key] if key in new else arr[left], axis=0)
    move_dev = np.insert(move_dev, left + 1, 0.0)
    at = left + 1 + np.arange(len(left))  # the new rows' indices
    pending = np.zeros(len(move_dev), bool)
    pending[at - 1] = pending[at] = True
    return pts, move_dev, pending


def refine_moves(points: dict, measure, tolerance: float, rounds: int = 8):
    """Split the moves of ``points`` (per-point arrays in path order, with ``tip`` and
    ``section``) until each is within ``tolerance`` (mm) of the CL curve (module doc).
    ``measure(points, i) -> (dev, splittable, new)`` checks the moves i -> i + 1 (k,):
    their deviations (k,), which of them may be split (bool, (k,) or a scalar) and the rows
    their mid-points would insert ({field: (k, ...)}). Returns (points with the new rows,
    the other arrays' values copied from the left neighbour; stats dict: ``chord_added``,
    ``chord_rounds``, ``chord_deviation`` = largest remaining deviation at the check
    points, ``chord_tolerance``)."""
    pts = dict(points)
    move_dev = np.zeros(max(len(pts["tip"]) - 1, 0))
    pending = pts["section"][1:] == pts["section"][:-1]
    added = done = 0
    while True:
        i = np.flatnonzero(pending)
        if len(i) == 0:
            break
        dev, splittable, new = measure(pts, i)
        move_dev[i] = dev
        bad = (move_dev[i] > tolerance) & splittable
        if not bad.any() or done == rounds:
            break
        done += 1
        left = i[bad]
        pts, move_dev, pending = split_moves(pts, move_dev, left,
                                             {k: v[bad] for k, v in new.items()})
        added += len(left)
    stats = {"chord_added": added, "chord_rounds": done,
             "chord_deviation": float(move_dev.max(initial=0.0)),
             "chord_tolerance": float(tolerance)}
    return pts, stats


def refine_chords(surface, cutter, place, points: dict, tolerance: float, rounds: int = 8):
    """:func:`refine_moves` against the tangent placement: ``points`` hold ``uv``, ``cc``,
    ``normal``, ``tip``, ``section`` (and any others); ``place(cutter, surface, cc,
    normal) -> tip``; the check points are placed at the CC points of the moves' quarter
    and mid XY, and only a mid-point on the footprint is inserted."""

    def measure(pts, i):
        xy = pts["cc"][:, :2]
        xy_q = (1 - _Q[:, None, None]) * xy[i] + _Q[:, None, None] * xy[i + 1]  # (3, k, 2)
        uv0 = np.broadcast_to(0.5 * (pts["uv"][i] + pts["uv"][i + 1]), xy_q.shape)
        ok, uv, cc, normal, tip = _placed(surface, cutter, place, xy_q.reshape(-1, 2),
                                          uv0.reshape(-1, 2))
        chord = (1 - _Q[:, None, None]) * pts["tip"][i] + _Q[:, None, None] * pts["tip"][i + 1]
        gap = np.linalg.norm(tip.reshape(3, -1, 3) - chord, axis=2)
        dev = np.nanmax(np.where(np.isnan(gap), -np.inf, gap), axis=0).clip(0.0)
        mid = len(i) + np.arange(len(i))  # the q = 1/2 rows of the flattened check points
        new = {"uv": uv[mid], "cc": cc[mid], "normal": normal[mid], "tip": tip[mid]}
        return dev, ok[mid], new

    return refine_moves(points, measure, tolerance, rounds)


def refine_drop_moves(points: dict, cutter, surface, tolerance: float, rounds: int = 8):
    """:func:`refine_moves` against the drop-cutter placement: where the tool falls away
    (past the edge, or where the tangent tool's XY swings round a corner of the part) the
    gouge-free tip follows a curve, and a chord below it would cut into the part. The check
    is vertical, at the move's own quarter and mid XY: exactly what the machine's straight
    move does; ``chord_deviation`` is then the largest vertical deviation left. ``points``
    hold ``tip`` and ``section``; an inserted row (the drop-cutter tip at the move's mid
    XY) repeats its left neighbour's other fields."""

    def measure(pts, i):
        tip = pts["tip"]
        xy = (1 - _Q[:, None, None]) * tip[i, :2] + _Q[:, None, None] * tip[i + 1, :2]
        chord_z = (1 - _Q[:, None]) * tip[i, 2] + _Q[:, None] * tip[i + 1, 2]
        z = cutter.drop_cutter(surface, xy.reshape(-1, 2)).reshape(3, -1)
        dev = np.max(np.abs(np.where(np.isfinite(z), z - chord_z, 0.0)), axis=0)
        return dev, True, {"tip": np.column_stack([xy[1], z[1]])}

    return refine_moves(points, measure, tolerance, rounds)
