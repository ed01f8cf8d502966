"""Reading an ISO / Fanuc G-code program (ours or another system's) into a toolpath.

Word-address blocks: ``( ... )`` and ``;`` comments, ``%`` and ``O`` lines, ``N`` block
numbers, and the words:

- motion (modal): ``G0`` rapid, ``G1`` feed, ``G2`` / ``G3`` arcs clockwise / counter-
  clockwise seen from the positive axis of the plane (``G17`` XY about +Z, ``G18`` ZX about
  +Y, ``G19`` YZ about +X), with the centre ``I J K`` (incremental from the start, the ISO
  default) or the radius ``R`` (negative: the arc over 180 degrees), the helix's third
  coordinate interpolated linearly; arcs become points within ``chord_tol``;
- ``G90`` / ``G91`` absolute / incremental coordinates, ``G20`` / ``G21`` inches / mm;
- ``G43 H`` (length compensation: X Y Z are the tip), ``G43.4 H`` (tool centre point control:
  X Y Z are the tip in the part frame, the rotary words set the tool axis through the
  machine's kinematics), ``G49`` cancels;
- ``X Y Z``, the rotary words of the kinematics (e.g. ``A C``), ``F`` (mm/min or in/min).

Words that do not move the tool are counted in ``ignored`` (``S``, ``T``, ``M``, ``H``, ``D``,
``G40 G54..G59 G80 G94 G64 G61``, ...). A motion word the reader does not take (canned
cycles ``G81..G89``, ``G28`` reference returns, tilted working planes ``G68``/``G68.2``, an
arc while a tilted plane or a non-vertical tool axis is active, polar ``G16``, the ``P`` word
of a ``G2``/``G3`` move (extra full turns of a helix), a subprogram call ``M98``/``M198``, ...)
is refused with ``LINE n: ...`` (``GcodeError``); a ``P`` on another block is counted.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from .apt_read import AptToolpath
from .arcs import PLANES, arc_points

INCH = 25.4
WORD = re.compile(r"([A-Z])\s*([+-]?(?:\d+\.?\d*|\.\d+))")
PAREN = re.compile(r"\([^()]*\)")
IGNORED_G = {"40", "49", "54", "55", "56", "57", "58", "59", "80", "94", "64", "61", "15", "69", "98", "99",
             "43", "43.4", "54.1", "5.1", "8", "61.1", "13.1", "90.1", "91.1"}
SUBPROGRAM_M = {98.0, 198.0}  # Fanuc subprogram calls (in memory, external)
REFUSED_G = {"28": "a reference return (G28)", "30": "a reference return (G30)", "16": "polar coordinates (G16)",
             "68": "a rotated plane (G68)", "68.2": "a tilted working plane (G68.2)", "17.1": "a tilted plane",
             "2.1": "a spiral", "12.1": "polar interpolation", "7.1": "cylindrical interpolation"}


class GcodeError(ValueError):
    def __init__(self, line: int, message: str):
        super().__init__(f"LINE {line}: {message}")
        self.line = line


def read_gcode(path: str | Path, cutter, kinematics=None,
               chord_tol: float = 0.01) -> AptToolpath:
    """The toolpath of a G-code program (module docstring) with the cutter (a
    ``cutters.Cutter``) given; ``kinematics`` (``export.kinematics.Kinematics``) turns rotary words
    into tool axes (None: a rotary word is refused)."""
    data = Path(path).read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise GcodeError(data[:e.start].count(b"\n") + 1, "not UTF-8 text") from None
    rot = (kinematics.tilt.name, kinematics.rotary.name) if kinematics is not None else ()
    pos = np.full(3, np.nan)
    ang = np.zeros(2)
    motion, plane, absolute, scale, feed, tilted = None, "17", True, 1.0, math.nan, False
    tips, axes, rapid, feeds = [], [], [], []
    ignored: dict[str, int] = {}

    def ign(word):
        ignored[word] = ignored.get(word, 0) + 1

    def axis_now():
        if kinematics is None:
            return np.array([0.0, 0.0, 1.0])
        return kinematics.tool_axis([ang[0]], [ang[1]])[0]

    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.split(";", 1)[0]
        if line.count("(") != line.count(")"):
            raise GcodeError(n, "unbalanced comment parentheses")
        code = PAREN.sub(" ", line).strip().upper()
        if not code or code == "%" or code.startswith("O"):
            continue
        rest = WORD.sub(" ", code).strip()
        if rest:
            raise GcodeError(n, f"not a G-code word: {rest.split()[0]!r}")
        words = WORD.findall(code)
        target = {}
        arc = {}
        new_rot = {}
        setting = False  # a block whose X Y Z I J K are parameters (G68 / G68.2 plane definition)
        line_motion = False  # the block names G0 / G1 / G2 / G3
        p_word = None
        for letter, value in words:
            if letter == "G":
                g = value.lstrip("0") or "0"
                g = g if "." not in g or not g.endswith("0") else g.rstrip("0").rstrip(".")
                if g in ("0", "1", "2", "3"):
                    motion, line_motion = g, True
                elif g in PLANES:
                    plane = g
                elif g == "90":
                    absolute = True
                elif g == "91":
                    absolute = False
                elif g == "20":
                    scale = INCH
                elif g == "21":
                    scale = 1.0
                elif g in REFUSED_G:
                    if g in ("68", "68.2", "17.1"):
                        tilted, setting = True, True
                    else:
                        raise GcodeError(n, f"{REFUSED_G[g]} is not supported")
                elif g == "69":
                    tilted = False
                elif g in IGNORED_G:
                    ign(f"G{g}")
                elif g.split(".")[0] in {str(k) for k in range(73, 90)}:
                    raise GcodeError(n, f"canned cycle G{g} is not supported (it moves the tool)")
                else:
                    raise GcodeError(n, f"G{g} is not supported")
            elif letter in "XYZ":
                target["XYZ".index(letter)] = float(value) * scale
            elif letter in "IJK":
                arc["IJK".index(letter)] = float(value) * scale
            elif letter == "R":
                arc["R"] = float(value) * scale
            elif letter == "F":
                feed = float(value) * scale
            elif rot and letter in rot:
                new_rot[rot.index(letter)] = float(value)
            elif letter in "ABCUVW":
                raise GcodeError(n, f"rotary word {letter} without the machine's kinematics"
                                 if not rot else f"word {letter} is not an axis of this machine ({', '.join(rot)})")
            elif letter == "M" and float(value) in SUBPROGRAM_M:
                raise GcodeError(n, f"M{value} calls a subprogram: its motion is not in this file")
            elif letter == "P":
                p_word = value
            elif letter in "NSTMHDQLE":
                ign(letter)
            else:
                raise GcodeError(n, f"unknown word {letter}{value}")
        if p_word is not None:
            if motion in ("2", "3") and (line_motion or target or new_rot):
                raise GcodeError(n, f"the P word (P{p_word}) of a G{motion} arc asks for extra full turns, "
                                    "which are not taken")
            ign("P")
        if setting:
            if line_motion:  # its X Y Z would be the plane's parameters, not the move's end
                raise GcodeError(n, "a motion word G0-G3 in a plane-definition block (G68 / G68.2 / G17.1)")
            continue
        if not target and not new_rot:
            if arc:
                raise GcodeError(n, "arc words without an end point")
            continue
        if motion is None:
            raise GcodeError(n, "a move before any G0/G1/G2/G3")
        end = pos.copy()
        for i, v in target.items():
            end[i] = v if absolute else (0.0 if np.isnan(pos[i]) else pos[i]) + v
        for i, v in new_rot.items():
            ang[i] = v if absolute else ang[i] + v
        if motion in ("2", "3"):
            if tilted:
                raise GcodeError(n, "an arc in a tilted working plane (G68 / G68.2) is not taken")
            ax = axis_now()
            if abs(ax[2] - 1.0) > 1e-9:
                raise GcodeError(n, "an arc with a tilted tool axis is not taken")
            if np.isnan(pos).any() or np.isnan(end).any():
                raise GcodeError(n, "an arc from an unknown position")
            for q in _arc(n, pos, end, arc, plane, motion == "2", chord_tol):
                tips.append(q)
                axes.append(ax)
                rapid.append(False)
                feeds.append(feed)
        elif arc:
            raise GcodeError(n, f"I/J/K/R on a G{motion} move")
        tips.append(end.copy())
        axes.append(axis_now())
        rapid.append(motion == "0")
        feeds.append(math.nan if motion == "0" else feed)
        pos = end
    if not tips:
        raise GcodeError(max(1, text.count("\n")), "no move: the file holds no toolpath")
    tip = np.array(tips, float)
    known = ~np.isnan(tip).any(axis=1)
    if not known.any():
        raise GcodeError(1, "no move with X, Y and Z known")
    first = int(np.flatnonzero(known)[0])
    axis = np.array(axes, float)
    multax = kinematics is not None and not np.allclose(axis, [0, 0, 1])
    return AptToolpath(tip=tip[first:], axis=axis[first:], rapid=np.array(rapid[first:], bool),
                       feed=np.array(feeds[first:], float), section=np.full(len(tip) - first, -1),
                       sections=(), cutter=cutter,
                       multax=multax, tip_is_centre=False, part=Path(path).name, ignored=ignored)


def _arc(n, start, end, arc, plane, clockwise, tol):
    """Points strictly inside the arc from start to end (the end is added by the caller)."""
    a, b, _ = PLANES[plane]
    p0, p1 = np.array([start[a], start[b]]), np.array([end[a], end[b]])
    if "R" in arc:
        r = arc["R"]
        chord = p1 - p0
        d = np.linalg.norm(chord)
        if d == 0 or abs(r) < d / 2 - 1e-6:
            raise GcodeError(n, f"arc radius R{r:g} does not reach the end point")
        h = math.sqrt(max(r * r - d * d / 4, 0.0))
        left = np.array([-chord[1], chord[0]]) / d
        # the centre side: a small arc (R > 0) turns less than 180 degrees
        sign = (1 if clockwise else -1) * (1 if r > 0 else -1)
        centre = p0 + chord / 2 - sign * h * left
        r = abs(r)
    else:
        off = np.array([arc.get(a, 0.0), arc.get(b, 0.0)])
        centre = p0 + off
        r = float(np.linalg.norm(off))
        if abs(np.linalg.norm(p1 - centre) - r) > max(1e-3, 1e-4 * r):
            raise GcodeError(n, f"the arc's end is {np.linalg.norm(p1 - centre):.4f} from its centre, "
                                f"not the radius {r:.4f}")
    if r <= 0:
        raise GcodeError(n, "an arc of zero radius")
    c3 = np.array(start, float)
    c3[a], c3[b] = centre
    return list(arc_points(start, end, c3, plane, clockwise, tol))
