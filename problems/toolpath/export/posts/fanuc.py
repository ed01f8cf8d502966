"""Fanuc 5-axis with tool centre point control, G43.4 (post ``fanuc``).

As ``iso`` (same program frame and words), plus the two rotary words of the machine's
kinematics (e.g. A and C) on every move where they change. ``G43.4 H n`` switches on tool
centre point control after the rotaries are set, so X Y Z are the tool tip in the part frame
while the control moves the linear axes to follow the rotation; ``G49`` cancels it at the end.
"""

from __future__ import annotations

from ..toolpath import Toolpath
from .base import Moves, Post, fmt, register
from .iso import IsoPost


@register
class FanucPost(IsoPost):
    name = "fanuc"
    five_axis = True
    arcs = False  # the 5-axis programs are written as linear blocks under G43.4 (rotaries interpolated)
    g_codes = Post.g_codes | {"43.4"}

    def header(self, tp: Toolpath, name: str, mv: Moves) -> list[str]:
        a, c = self.axis_names
        return self.start_lines(tp, name) + [f"G0 {a}{fmt(mv.angles[0, 0])} {c}{fmt(mv.angles[0, 1])}",
                                             f"G43.4 H{tp.tool.number}"]

    def footer(self, tp: Toolpath, name: str) -> list[str]:
        return ["G49", "M9", "M5", "M30", "%"]
