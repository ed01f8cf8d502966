"""ISO 6983 G-code for a 3-axis mill (post ``iso``).

Program: ``%``, ``O`` number, metric absolute XY plane (G21 G90 G17, cancels G40 G49 G80),
tool change ``T n M6``, spindle ``S n M3``, coolant ``M8``, work offset (G54...), then the
moves (G0 rapid, G1 feed with modal F; tool length compensation G43 H n on the first Z
move), and at the end a rapid to the safe Z, ``M9``, ``M5``, ``M30``, ``%``. Comments are
``( ... )``. The programmed point is the tool tip.
"""

from __future__ import annotations

import textwrap

from ..toolpath import Toolpath
from .base import Moves, Post, fmt, register


COMMENT_WIDTH = 70  # ( + 70 + ) = the 72 columns a control's editor shows


def _comment(text: str) -> list[str]:
    """``( ... )`` comment lines of at most 72 columns: a long text is split between words
    (never cut), parentheses inside become brackets."""
    clean = text.replace("(", "[").replace(")", "]").upper()
    return ["(" + part + ")" for part in textwrap.wrap(clean, COMMENT_WIDTH) or [""]]


@register
class IsoPost(Post):
    name = "iso"
    five_axis = False
    arcs = True  # G2 / G3 in G17 / G18 / G19, centre I J K incremental (with a machine tolerance)
    g_codes = Post.g_codes | {"43"}

    def start_lines(self, tp: Toolpath, name: str) -> list[str]:
        t = tp.tool
        title = _comment(name)
        lines = ["%", f"O{self.machine.program_number:04d} {title[0]}", *title[1:], *_comment(tp.name)]
        lines += [line for c in tp.comments for line in _comment(c)]
        lines += [*_comment(f"TOOL {t.number}: {t.label()}, TIP PROGRAMMED"), "G21 G90 G17 G40 G49 G80",
                  f"T{t.number} M6", f"S{t.spindle_rpm or 0:.0f} M3", "M8", self.machine.work_offset]
        return lines

    def header(self, tp: Toolpath, name: str, mv: Moves) -> list[str]:
        t = tp.tool
        safe = mv.tip[:, 2].max()
        return self.start_lines(tp, name) + [f"G0 G43 H{t.number} Z{fmt(safe)}"]

    def footer(self, tp: Toolpath, name: str) -> list[str]:
        return [f"G0 Z{fmt(tp.tip[:, 2].max())}", "M9", "M5", "M30", "%"]
