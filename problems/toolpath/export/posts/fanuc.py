"""Fanuc 5-axis with tool centre point control, G43.4 (post ``fanuc``).

As ``iso`` (same program frame and words), plus the two rotary words of the machine's
kinematics (e.g. A and C) on every move where they change. ``G43.4 H n`` switches on tool
centre point control after the rotaries are set, so X Y Z are the tool tip in the part frame
while the control moves the linear axes to follow the rotation; ``G49`` cancels it at the end.

Arcs (with a machine tolerance): ``G2`` / ``G3`` in ``G17`` / ``G18`` / ``G19`` with ``I J K``
incremental from the start, as ``iso``, and only in a program whose rotaries never move after
``G43.4`` (a 3-axis roughing or semi-finish on the 5-axis machine): the FANUC Series 30i
"Tool center point control for 5-axis machining" manual (A-79348E) allows circular
interpolation under ``G43.4`` when the table axes not normal to the plane stay where they were
when tool centre point control started (else alarm PS5421); a program with moving rotaries is
written as linear blocks.
"""

from __future__ import annotations

from ..toolpath import Toolpath
from .base import Moves, Post, fmt, register
from .iso import IsoPost


@register
class FanucPost(IsoPost):
    name = "fanuc"
    five_axis = True
    arcs = True  # only where the rotaries hold still in the whole program (Post.reduced)
    g_codes = Post.g_codes | {"43.4"}

    def header(self, tp: Toolpath, name: str, mv: Moves) -> list[str]:
        a, c = self.axis_names
        return self.start_lines(tp, name) + [f"G0 {a}{fmt(mv.angles[0, 0])} {c}{fmt(mv.angles[0, 1])}",
                                             f"G43.4 H{tp.tool.number}"]

    def footer(self, tp: Toolpath, name: str) -> list[str]:
        return ["G49", "M9", "M5", "M30", "%"]
