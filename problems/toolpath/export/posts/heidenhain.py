"""Heidenhain TNC conversational (Klartext) 5-axis with ``FUNCTION TCPM`` (post ``heidenhain``).

Every line starts with its block number (0, 1, ...). Program: ``BEGIN PGM name MM``,
``TOOL CALL n Z S rpm``, the rotaries positioned, ``FUNCTION TCPM F TCP AXIS POS PATHCTRL
AXIS`` (tool centre point control, the successor of M128: X Y Z are the tool tip in the part
frame), linear blocks ``L X+.. Y+.. Z+.. A+.. C+.. R0 F..`` (``FMAX`` for rapids; the first
block switches spindle and coolant on with M13), ``FUNCTION RESET TCPM``, the end block at the
clearance plane with ``M30``, ``END PGM name MM``. Comments are ``; ...`` lines.

Arcs (with a machine tolerance, where the rotaries hold still): the circle centre ``CC`` with
the two coordinates of the arc's plane (absolute; ``CC X.. Y..`` in XY, ``CC X.. Z..`` in ZX,
``CC Y.. Z..`` in YZ: the pair names the plane), then the circular path ``C`` to the end point
in that plane with the direction ``DR+`` (mathematically positive: from the plane's reference
axis towards its second axis, X to Y, Z to X, Y to Z, i.e. counter-clockwise seen from the
positive third axis, as G3) or ``DR-`` (clockwise, as G2), as in the HEIDENHAIN TNC user's
manuals (Klartext programming, "Path contours - Cartesian coordinates": circle centre CC,
circular path C around CC). Words are written in X Y Z order. Start and end lie on the circle
(the control accepts a radius mismatch up to 0.016 mm; ours is the 4th decimal). As with
``fanuc``, arcs are written only when the rotaries do not move in the whole program.
"""

from __future__ import annotations

import re

from ..toolpath import Toolpath
from .base import Moves, Post, fmt, register

TCPM_ON = "FUNCTION TCPM F TCP AXIS POS PATHCTRL AXIS"
_NUM = r"[+-]\d+(?:\.\d*)?"
_PLANE_OF = {frozenset("XY"): "17", frozenset("XZ"): "18", frozenset("YZ"): "19"}


def _signed(v: float) -> str:
    s = fmt(v).rstrip(".")
    return s if s.startswith("-") else "+" + s


@register
class HeidenhainPost(Post):
    name = "heidenhain"
    five_axis = True
    extension = ".h"
    arcs = True  # CC + C DR+/- in XY, ZX, YZ (with a machine tolerance)

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

    def arc_lines(self, plane: str, clockwise: bool, end: dict[str, str], start, centre, feed: str | None,
                  last: dict) -> list[str]:
        """``CC`` (absolute centre, the plane's two axes in X Y Z order; modal, so written
        only when it changes) and ``C`` (module docstring); CC's axes name the plane."""
        axes = sorted(end)
        cc = "CC " + " ".join(f"{k}{_signed(centre['XYZ'.index(k)])}" for k in axes)
        to = " ".join(f"{k}{_signed(float(end[k]))}" for k in axes)
        tail = f" F{float(feed):.0f}" if feed is not None else ""
        lines = [] if last.get("CC") == cc else [cc]
        last["CC"] = cc
        return lines + [f"C {to} {'DR-' if clockwise else 'DR+'}{tail}"]

    def footer(self, tp: Toolpath, name: str) -> list[str]:
        # the program already stands at the clearance plane: the end block stays there (it
        # went down to the toolpath's highest point, below the plane, with the table tilted)
        return ["FUNCTION RESET TCPM", f"L Z{_signed(self.machine.plane(tp))} R0 FMAX M30", f"END PGM {name} MM"]

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
        cc = re.fullmatch(rf"CC ([XYZ])({_NUM}) ([XYZ])({_NUM})", code)
        if cc:
            pair = frozenset((cc.group(1), cc.group(3)))
            if len(pair) != 2:
                raise ValueError("CC names one axis twice")
            state["CC"] = {cc.group(1): float(cc.group(2)), cc.group(3): float(cc.group(4))}
            return False
        if code.startswith("C "):
            return self._circle(code, state)
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

    def _circle(self, code: str, state: dict) -> bool:
        """A ``C X.. Y.. DR+/- [F..]`` block about the last ``CC``: the base reader's arc state
        (G2 / G3, the plane CC names, the centre incremental from the start)."""
        blk = re.fullmatch(rf"C ([XYZ])({_NUM}) ([XYZ])({_NUM}) DR([+-])(?: F(\d+))?", code)
        if not blk:
            raise ValueError("not a C X.. Y.. DR+/- [F..] block")
        end = {blk.group(1): float(blk.group(2)), blk.group(3): float(blk.group(4))}
        cc = state.get("CC")
        if cc is None:
            raise ValueError("a circular path C before any circle centre CC")
        if set(end) != set(cc):
            raise ValueError(f"C in {''.join(sorted(end))}, the centre CC in {''.join(sorted(cc))}")
        start = {k: state[k] for k in end}
        if any(v != v for v in start.values()):
            raise ValueError("a circular path from an unknown position")
        state["plane"] = _PLANE_OF[frozenset(end)]
        state["IJK"] = {"IJK"["XYZ".index(k)]: cc[k] - start[k] for k in end}
        state["G"] = "G2" if blk.group(5) == "-" else "G3"
        if blk.group(6):
            state["F"] = float(blk.group(6))
        if state["F"] != state["F"]:
            raise ValueError("a circular path before any F")
        state.update(end)
        return True
