"""Edge overrun: a section that ends on the footprint's edge runs on past it.

A pass that stops with its last CC point on the part's edge leaves the edge row between two
passes higher than the scallop inside: the tool's swept profile across the feed only forms
the designed cusp where both neighbouring passes sweep the tool over the point, and at a
section's end the tool stops with its centre short of the end CC point wherever the surface
rises towards the edge (measured by the cut simulation: 0.41 mm in the last 0.1 mm row of
Choi's surface against 0.25 mm inside, h_c 0.254; 0.35 mm at the pass ends of Fountas' VEGA
set against 0.10 mm with the run-on). So every section end on the footprint's boundary gets
``n`` more CL points along the travel, until the tool's centre reaches the end CC point;
``planner.py`` adds, for a 3-axis drop-cutter plan, how far the plane's band extends past
the plane along an oblique edge (the wedge between two passes that meet the edge at
different places). Where the surface falls towards the end (the tool's centre already
past the end CC point along the travel, so the rules above add nothing), the centre runs on
until it is past the end CC point by the contact's horizontal distance rho from the axis
(``reach``; rho is the along-travel offset alone where the surface slopes only along the
feed, so nothing is added then, and a ball on a plane needs nothing there: the lowest
position of its lower surface above any point beside the contact comes before the contact
reaches the edge). Measured on Choi's surface (torus r 1, h_c 0.254 mm, 0.05 mm grid, the
AMAS plan): without it the edge column, where a zone's passes end on the part's edge with
the surface falling towards it along and across the feed, rose to 0.307 mm against
<= 0.28 mm inside (run-ons of 0.1-2 mm all brought it down). The wedge is added to that
reach, not compared with it: rho only brings the centre abeam of the end CC point, and the
band's material along an oblique edge lies further on. With the larger of the two alone,
the single-zone plan of Choi's surface (torus r 1, feed 11.5 deg) left 0.336 mm (0.1 mm
grid) at the corner (50.8, 76.2), where a pass ends on the top edge 1.5 mm short of the
corner with its tool 1.9 mm downhill across the feed. A 3-axis tool keeps its height from
the drop-cutter (it touches the part's edge and nowhere penetrates it); a 5-axis tool runs on along the travel tangent with
the end point's axis.

The extra points hold no CC point (``on_part`` False): their CC fields repeat the end
point's, shifted along the travel tangent; their moves count in the plan's lengths.
"""

from __future__ import annotations

import numpy as np

from ..geometry.rows import ranges
from ..geometry.vectors import row_norms, take_rows

__all__ = ["edge_overrun"]


def edge_overrun(points: dict, sec_start, sec_count, at_head, at_tail, head_length,
                 tail_length, ahead, n: int = 3, reach=None):
    """Insert the overrun points. ``points``: per-point arrays in machining order (must hold
    ``p`` and ``tangent``); ``at_head`` / ``at_tail`` (S,): the section's first / last point
    lies on the footprint's edge; ``head_length`` / ``tail_length`` (S,) mm: how far past
    the first / last CC point the tool's centre goes; ``ahead`` (N,): how far along the
    travel the tool's centre already is from each CC point (a vertical cutter tangent on a
    slope sits downhill of its contact), so only the rest is added; ``reach`` (N,) mm,
    optional: how far past an end CC point the centre goes, beyond the wedge, where the
    surface falls towards that end (the centre already past it). Returns (points with the
    new rows, sec_start, sec_count, on_part (N',), shift (N', 3) the offset of each row from
    the point it repeats, (seg_sec, seg_len) of the added moves)."""
    sec_start, sec_count = np.asarray(sec_start), np.asarray(sec_count)
    first, last = sec_start, sec_start + sec_count - 1
    ahead = np.asarray(ahead, float)
    head_length, tail_length = np.asarray(head_length, float), np.asarray(tail_length, float)
    if reach is not None:  # where the surface falls towards the end: the tool's centre
        # is past the end CC point already (ahead of it along the travel towards the edge)
        reach = np.asarray(reach, float)
        # rho past the end brings the centre abeam of the end CC point; the wedge of the
        # band lies beyond that, so the two add up
        head_length = head_length + np.where(ahead[first] < 0, reach[first], 0.0)
        tail_length = tail_length + np.where(ahead[last] > 0, reach[last], 0.0)
    # how far the tool's centre still has to go past each end (0: it is already there)
    reach_head = np.maximum(head_length + ahead[first], 0.0)
    reach_tail = np.maximum(tail_length - ahead[last], 0.0)
    head = np.where(np.asarray(at_head) & (reach_head > 1e-6), n, 0)
    tail = np.where(np.asarray(at_tail) & (reach_tail > 1e-6), n, 0)
    count = sec_count + head + tail
    start = np.cumsum(count) - count
    owner, j = ranges(count)  # j: the position in the new section
    h, c = head[owner], sec_count[owner]
    body = np.clip(j - h, 0, c - 1)
    src = sec_start[owner] + body
    # how many steps before the first point (< 0) or after the last one (> 0)
    steps = np.where(j < h, j - h, np.where(j >= h + c, j - h - c + 1, 0))
    # along the travel tangent, scaled to unit length in XY: a 3-axis tool keeps only the
    # XY part (its height comes from the drop-cutter), a 5-axis one runs on along the tangent
    t = take_rows(points["tangent"], src)
    t_xy = np.maximum(row_norms(t[:, :2]), 1e-9)
    step_len = np.where(steps < 0, reach_head[owner], reach_tail[owner]) / n
    shift = t * (steps * step_len / t_xy)[:, None]
    out = {k: take_rows(v, src) for k, v in points.items()}
    out["p"] = out["p"] + shift
    out["chord"] = np.where(steps == 0, out["chord"], 0.0)
    added = steps != 0
    return out, start, count, ~added, shift, (owner[added], (step_len / t_xy)[added])
