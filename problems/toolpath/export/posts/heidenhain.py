"""Heidenhain TNC conversational (Klartext) 5-axis with ``FUNCTION TCPM`` (post ``heidenhain``).

Every line starts with its block number (0, 1, ...). Program: ``BEGIN PGM name MM``,
``TOOL CALL n Z S rpm``, the rotaries positioned, ``FUNCTION TCPM F TCP AXIS POS PATHCTRL
AXIS`` (tool centre point control, the successor of M128: X Y Z are the tool tip in the part
frame), linear blocks ``L X+.. Y+.. Z+.. A+.. C+.. R0 F..`` (``FMAX`` for rapids; the first
block switches spindle and coolant on with M13), ``FUNCTION RESET TCPM``, a retract with
``M30``, ``END PGM name MM``. Comments are ``; ...`` lines.
"""

from __future__ import annotations

import re

from ..toolpath import Toolpath
from .base import Moves, Post, fmt, register

TCPM_ON = "FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS"
_NUM = r"[+-]\d+(?:\.\d*)?"


def _signed(v: float) -> str:
    s = fmt(v).rstrip(".")
    return s if s.startswith("-") else "+" + s


@register
class HeidenhainPost(Post):
    name = "heidenhain"
    five_axis = True
    extension = ".h"

    def program(self, tp: Toolpath, name: str = "EVOPLAN") -> str:
        body = super().program(tp, name).splitlines()
        return "\n".join(f"{n} {line}" for n, line in enumerate(body)) + "\n"

    def header(self, tp: Toolpath, name: str, mv: Moves) -> list[str]:
        t, (a, c) = tp.tool, self.axis_names
        lines = [f"BEGIN PGM {name} MM", f"; {tp.name}"] + [f"; {x}" for x in tp.comments]
        lines += [f"; TOOL {t.number}: {t.label()}, TIP PROGRAMMED", f"TOOL CALL {t.number} Z S{t.spindle_rpm or 0:.0f}",
                  f"L Z{_signed(mv.tip[:, 2].max())} R0 FMAX M13",
                  f"L {a}{_signed(mv.angles[0, 0])} {c}{_signed(mv.angles[0, 1])} R0 FMAX", TCPM_ON]
        return lines

    def block(self, motion: str, words: dict[str, str], feed: str | None, new_motion: bool) -> str:
        parts = ["L"] + [f"{k}{_signed(float(v))}" for k, v in words.items()] + ["R0"]
        parts.append("FMAX" if motion == "G0" else f"F{float(feed):.0f}" if feed is not None else "")
        return " ".join(p for p in parts if p)

    def footer(self, tp: Toolpath, name: str) -> list[str]:
        return ["FUNCTION RESET TCPM", f"L Z{_signed(tp.tip[:, 2].max())} R0 FMAX M30", f"END PGM {name} MM"]

    def parse_line(self, line: str, state: dict) -> bool:
        m = re.fullmatch(r"(\d+) (.*)", line.strip())
        if not m:
            raise ValueError("no block number")
        n, code = int(m.group(1)), m.group(2).strip()
        if n != state.setdefault("block", 0):
            raise ValueError(f"block number {n}, expected {state['block']}")
        state["block"] += 1
        if code.startswith(";") or code == TCPM_ON or code == "FUNCTION RESET TCPM" \
                or re.fullmatch(r"(BEGIN|END) PGM \w+ MM|TOOL CALL \d+ Z S\d+", code):
            return False
        axes = {"X": "X", "Y": "Y", "Z": "Z", self.axis_names[0]: "A0", self.axis_names[1]: "A1"}
        letters = "".join(axes)
        blk = re.fullmatch(rf"L((?: [{letters}]{_NUM})*) R0(?: (FMAX|F\d+))?(?: (M13|M30))?", code)
        if not blk:
            raise ValueError("not a BEGIN/END PGM, TOOL CALL, FUNCTION TCPM or L block")
        moved = False
        for word in blk.group(1).split():
            state[axes[word[0]]] = float(word[1:])
            moved = True
        # FMAX holds for its own block only; F is modal
        state["G"] = "G0" if blk.group(2) == "FMAX" else "G1"
        if blk.group(2) and blk.group(2) != "FMAX":
            state["F"] = float(blk.group(2)[1:])
        if moved and state["G"] == "G1" and state["F"] != state["F"]:
            raise ValueError("a feed move before any F")
        return moved
