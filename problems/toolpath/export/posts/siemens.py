"""Siemens Sinumerik 840D 5-axis with ``TRAORI`` (post ``siemens``).

Program: ``;`` comments, ``G17 G90 G71`` (metric), work offset, ``T n`` ``M6`` ``D1``,
``S n M3``, ``M8``, the rotaries set, then ``TRAORI`` (5-axis transformation: X Y Z are the
tool tip in the part frame) with ``ORIAXES`` (the rotary axes interpolated linearly), the
moves (G0/G1, modal F), ``TRAFOOF``, ``M9``, ``M5``, ``M30``.

Arcs (with a machine tolerance, in a program whose rotaries never move): ``G2`` / ``G3`` in
``G17`` / ``G18`` / ``G19``, the end point's two in-plane coordinates and the centre ``I J K``
incremental from the start (Siemens' default for I J K; ``I=AC(..)`` would be absolute), the
direction seen from the positive axis normal to the plane, as in the SINUMERIK 840D sl
Programming Manual Fundamentals ("Circular interpolation with center point and end point").
The radius form ``CR=`` is not written (it is ambiguous at 180 degrees).
"""

from __future__ import annotations

from ..toolpath import Toolpath
from .base import Moves, Post, fmt, register


@register
class SiemensPost(Post):
    name = "siemens"
    five_axis = True
    extension = ".mpf"
    arcs = True  # G2 / G3 with I J K in G17 / G18 / G19 (with a machine tolerance)
    keywords = frozenset({"TRAORI", "TRAFOOF", "ORIAXES"})
    g_codes = Post.g_codes | {"71"}

    def strip_comment(self, line: str) -> str:
        return line.split(";", 1)[0]

    def header(self, tp: Toolpath, name: str, mv: Moves) -> list[str]:
        t, (a, c) = tp.tool, self.axis_names
        lines = [f"; {name}", f"; {tp.name}"] + [f"; {x}" for x in tp.comments]
        lines += [f"; TOOL {t.number}: {t.label()}, TIP PROGRAMMED", "G17 G90 G71", self.machine.work_offset,
                  f"T{t.number} M6", "D1", f"S{t.spindle_rpm or 0:.0f} M3", "M8",
                  f"G0 {a}{fmt(mv.angles[0, 0])} {c}{fmt(mv.angles[0, 1])}", "TRAORI", "ORIAXES"]
        return lines

    def footer(self, tp: Toolpath, name: str) -> list[str]:
        return ["TRAFOOF", "M9", "M5", "M30"]
