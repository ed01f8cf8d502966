"""Post-processors: one small class per NC dialect, one registry (``POSTS``).

A post turns a ``toolpath.Toolpath`` (tool tips, unit axes, rapid/plunge flags) into NC text.
The shared part lives here: rotary angles from the tool axes through the machine's
``kinematics.Kinematics`` (5-axis posts; tool-centre-point control, so the programmed X Y Z
is the tool tip in part coordinates), unwind/reposition moves where the angles would jump,
modal words (a coordinate or feed is written only when it changes), and reading a program
back (``read``) so that every line written is checked by a grammar.

The reader is a small strict grammar of our own rather than a general G-code library: a
word-address parser would accept many lines the posts never write, and would not read
Heidenhain's conversational blocks at all; a grammar of exactly what is written turns any
malformed or foreign line into an error, which is what the round-trip tests need.

A dialect subclasses :class:`Post`, sets ``name``/``five_axis``, writes ``header``,
``block`` and ``footer``, and parses its own lines in ``parse_line``; ``@register`` adds it
to ``POSTS``. A dialect that has circular interpolation declares ``arcs = True``: with a
machine ``tolerance``, its programs then carry arcs fitted within that chord tolerance
(``export/arcs.py``), written by ``arc_lines`` (``G2`` / ``G3`` with ``I J K`` by default; a
dialect with another syntax overrides it and reads it back in ``parse_line``). Any post, given a ``tolerance``, merges collinear and
near-collinear cutting points within it (5-axis posts only where the rotaries hold still,
which a 3-axis roughing path does).
"""

from __future__ import annotations

import copy
import re
from dataclasses import dataclass

import numpy as np

from ..kinematics import Kinematics
from ..toolpath import Toolpath

POSTS: dict[str, type["Post"]] = {}


def register(cls):
    """Class decorator: add a post to the registry under its ``name``."""
    POSTS[cls.name] = cls
    return cls


MAX_BLOCKS = 20_000_000  # moves of one NC program


class PostError(ValueError):
    """A toolpath this post or machine cannot write (one line)."""


@dataclass
class Machine:
    """What the posts need of the machine: kinematics (5-axis posts), work offset, program
    number, the retract distance along the tool axis of a reposition, and the clearance plane
    ``safe_z`` (absolute Z; None: ``clearance`` above the toolpath's highest point): rotary
    turns above the kinematics' ``rotary_threshold`` happen there, every 5-axis program
    starts and ends there."""

    kinematics: Kinematics | None = None
    work_offset: str = "G54"
    program_number: int = 1000
    clearance: float = 10.0
    safe_z: float | None = None
    tolerance: float | None = None  # chord tolerance of point reduction and arcs (None: every point)

    def plane(self, tp: Toolpath) -> float:
        """The clearance plane's Z for this toolpath."""
        return float(tp.tip[:, 2].max() + self.clearance) if self.safe_z is None else float(self.safe_z)


@dataclass
class Moves:
    """What a program does, as read back: tip (k, 3), angles (k, 2) (nan: not a 5-axis
    program), rapid (k,), feed (k,) mm/min (nan for rapids)."""

    tip: np.ndarray
    angles: np.ndarray
    rapid: np.ndarray
    feed: np.ndarray


def fmt(v: float, digits: int = 4) -> str:
    """A coordinate with a decimal point and no trailing zeros: 12.5 -> '12.5', 12 -> '12.'."""
    s = f"{v:.{digits}f}".rstrip("0")
    return "0." if s in ("-0.", "0.", "-.") else s


class Post:
    name = ""
    five_axis = True
    extension = ".nc"
    arcs = False  # the dialect writes (and reads back) G2 / G3 arcs in G17 / G18 / G19

    def __init__(self, machine: Machine | None = None):
        self.machine = machine or Machine()
        if self.five_axis and self.machine.kinematics is None:
            raise PostError(f"post {self.name}: a 5-axis post needs the machine kinematics")

    @property
    def axis_names(self) -> tuple[str, str]:
        k = self.machine.kinematics
        return (k.tilt.name, k.rotary.name) if k is not None else ("", "")

    # ------------------------------------------------------------------ the moves
    def moves(self, tp: Toolpath) -> Moves:
        """The moves the program makes (5-axis): a rapid over the first point at the clearance
        plane, the toolpath's points with their angles, a reposition through the clearance
        plane (retract along the axis, rise, turn, move over, come down) wherever the kinematics
        flags an unwind or a rotary turns by more than ``rotary_threshold`` below the plane,
        smaller turns above ``max_step`` split into equal steps, and a final retract to the
        clearance plane (before the footer cancels TCP)."""
        feed = np.where(tp.rapid, np.nan, np.where(tp.plunge, tp.plunge_feed, tp.feed))
        if not self.five_axis:
            if tp.multi_axis:
                raise PostError(f"post {self.name} is 3-axis: toolpath {tp.name!r} has tilted tool axes")
            return Moves(tp.tip.copy(), np.full((len(tp.tip), 2), np.nan), tp.rapid.copy(), feed)
        kin = self.machine.kinematics
        ang, unwind = kin.angles(tp.axis)
        turns = np.nan_to_num(np.abs(np.diff(ang, axis=0)).max(axis=1, initial=0.0)) if len(ang) > 1 else np.zeros(0)
        blocks = len(ang) + float(np.maximum(np.ceil(turns / kin.max_step - 1e-9) - 1, 0).sum())
        if blocks > MAX_BLOCKS:  # estimated before the moves are written out
            raise ValueError(f"post.kinematics.max_step: {kin.max_step:g} degrees splits toolpath {tp.name!r} into "
                             f"{blocks:.3g} NC blocks (at most {MAX_BLOCKS:,})")
        safe, c = self.machine.plane(tp), self.machine.clearance
        real = kin.tool_axis(ang[:, 0], ang[:, 1])  # differs from tp.axis where the table holds near the pole
        self.axis_error = float(np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", real, tp.axis), -1, 1))).max())
        tp_tip = tp.tip
        if tp.tool.cutter.spherical:  # a ball: keep its centre
            tp_tip = tp.tip + tp.tool.cutter.centre_height * (tp.axis - real)
        tp = copy.copy(tp)
        tp.tip = tp_tip
        tip, angles, rapid, f = [], [], [], []

        def add(p, a, is_rapid, feed_n):
            tip.append(np.asarray(p, float))
            angles.append(a)
            rapid.append(bool(is_rapid))
            f.append(np.nan if is_rapid else feed_n)

        add([tp.tip[0, 0], tp.tip[0, 1], max(safe, tp.tip[0, 2])], ang[0], True, np.nan)
        for n in range(len(tp.tip)):
            feed_n = feed[n]
            turn = np.abs(ang[n] - ang[n - 1]).max() if n else 0.0
            high = n and min(tp.tip[n - 1, 2], tp.tip[n, 2]) >= safe - 1e-9
            if n and (unwind[n] or turn > kin.rotary_threshold) and not high:
                # retract along the axis, rise to the clearance plane, turn there, come down
                up = tp.tip[n - 1] + c * tp.axis[n - 1]
                over = tp.tip[n] + c * tp.axis[n]
                add(up, ang[n - 1], True, np.nan)
                add([up[0], up[1], max(safe, up[2])], ang[n - 1], True, np.nan)
                add([up[0], up[1], max(safe, up[2])], ang[n], True, np.nan)
                add([over[0], over[1], max(safe, over[2])], ang[n], True, np.nan)
                add(over, ang[n], True, np.nan)
                if not tp.rapid[n]:
                    feed_n = tp.plunge_feed
            elif n > 0:
                k = int(np.ceil(turn / kin.max_step - 1e-9))
                for i in range(1, k):  # the control's own linear interpolation, written out
                    add(tp.tip[n - 1] + i / k * (tp.tip[n] - tp.tip[n - 1]),
                        ang[n - 1] + i / k * (ang[n] - ang[n - 1]), tp.rapid[n], feed_n)
            add(tp.tip[n], ang[n], tp.rapid[n], feed_n)
        last = tp.tip[-1]
        if last[2] < safe - 1e-9:  # every program ends at the clearance, before TCP is cancelled
            up = last if tp.rapid[-1] else last + c * tp.axis[-1]
            if not tp.rapid[-1]:
                add(up, ang[-1], True, np.nan)
            add([up[0], up[1], max(safe, up[2])], ang[-1], True, np.nan)
        return Moves(np.array(tip), np.array(angles), np.array(rapid), np.array(f))

    # ------------------------------------------------------------------ writing
    def reduced(self, mv: Moves):
        """The moves' reduction within the machine's tolerance (``arcs.Reduced``), or None:
        no tolerance, or a 5-axis program whose rotaries move."""
        tol = self.machine.tolerance
        if tol is None or len(mv.tip) < 3:
            return None
        if self.five_axis and not np.allclose(mv.angles, mv.angles[0], atol=0.0, rtol=0.0):
            return None
        from ..arcs import reduce_moves

        return reduce_moves(mv.tip, mv.rapid, mv.feed, tol, self.arcs)

    def program(self, tp: Toolpath, name: str = "EVOPLAN") -> str:
        """The whole NC program of one operation."""
        mv = self.moves(tp)
        red = self.reduced(mv)
        lines = self.header(tp, name.upper(), mv)
        last: dict[str, str] = {"plane": "17"}
        prev = 0
        for n in range(len(mv.tip)):
            if red is not None and not red.keep[n]:
                continue
            if red is not None and red.motion[n] >= 2:
                lines += self._arc_block(mv, red, prev, n, last)
                prev = n
                continue
            prev = n
            words = {"X": fmt(mv.tip[n, 0]), "Y": fmt(mv.tip[n, 1]), "Z": fmt(mv.tip[n, 2])}
            if self.five_axis:
                words[self.axis_names[0]] = fmt(mv.angles[n, 0])
                words[self.axis_names[1]] = fmt(mv.angles[n, 1])
            changed = {k: v for k, v in words.items() if last.get(k) != v}
            if not changed:
                continue  # the tool is already there
            feed = None if mv.rapid[n] else fmt(mv.feed[n], 1)
            if feed is not None and last.get("F") == feed:
                feed = None
            motion = "G0" if mv.rapid[n] else "G1"
            lines.append(self.block(motion, changed, feed, motion != last.get("G")))
            last.update(words, G=motion, **({"F": feed} if feed is not None else {}))
        lines += self.footer(tp, name.upper())
        return "\n".join(lines) + "\n"

    def _arc_block(self, mv: Moves, red, start: int, n: int, last: dict) -> list[str]:
        """The lines of the arc from point ``start`` to point ``n`` (``arc_lines``); the arc is
        planar (``arcs.fit_blocks``: the normal coordinate is the start's within 1e-7 mm), so
        only its two in-plane end coordinates are written."""
        from ..arcs import PLANES

        plane = red.plane[n]
        a, b, _ = PLANES[plane]
        p, q, centre = mv.tip[start], mv.tip[n], red.centre[n]
        end = {"XYZ"[a]: fmt(q[a]), "XYZ"[b]: fmt(q[b])}
        feed = fmt(mv.feed[n], 1)
        if last.get("F") == feed:
            feed = None
        lines = self.arc_lines(plane, int(red.motion[n]) == 2, end, p, centre, feed, last)
        last.update(end, G=f"G{int(red.motion[n])}", plane=plane, **({"F": feed} if feed is not None else {}))
        return lines

    def arc_lines(self, plane: str, clockwise: bool, end: dict[str, str], start, centre, feed: str | None,
                  last: dict) -> list[str]:
        """An arc in word-address G-code (ISO 6983; Fanuc, Siemens): ``G2`` / ``G3`` (with
        the plane word ``G17`` / ``G18`` / ``G19`` when it differs from ``last["plane"]``,
        the modal words written so far), the end point's two in-plane coordinates and the
        centre ``I J K`` incremental from the start."""
        from ..arcs import PLANES

        a, b, _ = PLANES[plane]
        words = dict(end)
        words["IJK"[a]] = fmt(centre[a] - start[a])
        words["IJK"[b]] = fmt(centre[b] - start[b])
        motion = "G2" if clockwise else "G3"
        return [self.block(motion if plane == last["plane"] else f"G{plane} {motion}", words, feed, True)]

    def header(self, tp: Toolpath, name: str, mv: Moves) -> list[str]:  # pragma: no cover - abstract
        raise NotImplementedError

    def block(self, motion: str, words: dict[str, str], feed: str | None, new_motion: bool) -> str:
        """One motion line; by default word-address G-code with modal G0/G1."""
        parts = [motion] if new_motion else []
        parts += [f"{k}{v}" for k, v in words.items()]
        if feed is not None:
            parts.append(f"F{feed}")
        return " ".join(parts)

    def footer(self, tp: Toolpath, name: str) -> list[str]:  # pragma: no cover - abstract
        raise NotImplementedError

    # ------------------------------------------------------------------ reading
    def read(self, text: str) -> Moves:
        """Parse a program this post wrote; ValueError ``line n: ...`` for a line the
        dialect's grammar rejects."""
        state = {"G": None, "F": np.nan, "X": np.nan, "Y": np.nan, "Z": np.nan, "A0": np.nan, "A1": np.nan,
                 "plane": "17", "IJK": {}}
        tip, ang, rapid, feed = [], [], [], []
        for n, line in enumerate(text.splitlines(), 1):
            try:
                move = self.parse_line(line, state)
                if move and state["G"] in ("G2", "G3"):
                    inner = self._arc_inner(tip[-1] if tip else None, state)
                    tip += inner
                    ang += [[state["A0"], state["A1"]]] * len(inner)
                    rapid += [False] * len(inner)
                    feed += [state["F"]] * len(inner)
            except ValueError as exc:
                raise ValueError(f"line {n}: {exc}: {line[:60]!r}") from None
            if move:
                tip.append([state["X"], state["Y"], state["Z"]])
                ang.append([state["A0"], state["A1"]])
                rapid.append(state["G"] == "G0")
                feed.append(np.nan if state["G"] == "G0" else state["F"])
        return Moves(np.array(tip, float).reshape(-1, 3), np.array(ang, float).reshape(-1, 2),
                     np.array(rapid, bool), np.array(feed, float))

    # word-address G-code (ISO, Fanuc, Siemens): the grammar of ``parse_line``
    letters = "NOGXYZFSTMHD"
    keywords: frozenset[str] = frozenset()
    g_codes = frozenset({"0", "1", "17", "21", "40", "49", "80", "90", "54", "55", "56", "57", "58", "59"})
    m_codes = frozenset({"3", "5", "6", "8", "9", "30"})

    READ_TOL = 1e-3  # mm: chord tolerance of the points an arc is read back as

    def _arc_inner(self, start, state: dict) -> list:
        """The points strictly inside the arc just read (``arcs.arc_points``)."""
        from ..arcs import PLANES, arc_points

        if start is None or np.isnan(start).any():
            raise ValueError("an arc from an unknown position")
        a, b, _ = PLANES[state["plane"]]
        ijk = state["IJK"]
        if set(ijk) - {"IJK"[a], "IJK"[b]}:
            raise ValueError(f"centre words {''.join(sorted(ijk))} outside plane G{state['plane']}")
        centre = np.array(start, float)
        for k, v in ijk.items():
            centre["IJK".index(k)] += v
        end = np.array([state["X"], state["Y"], state["Z"]])
        r0, r1 = (float(np.hypot(p[a] - centre[a], p[b] - centre[b])) for p in (start, end))
        if r0 == 0 or abs(r1 - r0) > max(1e-3, 1e-4 * r0):
            raise ValueError(f"the arc's end is {r1:.4f} from its centre, not the radius {r0:.4f}")
        return arc_points(start, end, centre, state["plane"], state["G"] == "G2", self.READ_TOL).tolist()

    def strip_comment(self, line: str) -> str:
        """The line without its comment: ``( ... )`` in ISO/Fanuc."""
        if line.count("(") != line.count(")"):
            raise ValueError("unbalanced comment parentheses")
        return _PARENS.sub(" ", line)

    def parse_line(self, line: str, state: dict) -> bool:
        """Update the modal ``state`` from one line; True if the line moves the tool."""
        code = self.strip_comment(line).strip().upper()
        if not code or code == "%":
            return False
        moved = False
        state["IJK"] = {}
        axes = {"X": "X", "Y": "Y", "Z": "Z"}
        if self.five_axis:
            axes.update({self.axis_names[0]: "A0", self.axis_names[1]: "A1"})
        for token in code.split():
            if token in self.keywords:
                continue
            m = _WORD.fullmatch(token)
            if not m or (m.group(1) not in self.letters and m.group(1) not in axes
                         and not (self.arcs and m.group(1) in "IJK")):
                raise ValueError(f"unknown word {token!r}")
            letter, value = m.group(1), m.group(2)
            if self.arcs and letter in "IJK":
                state["IJK"][letter] = float(value)
            elif letter in axes:
                state[axes[letter]] = float(value)
                moved = True
            elif letter == "G":
                g = value.lstrip("0") or "0"
                if g in ("0", "1") or (self.arcs and g in ("2", "3")):
                    state["G"] = "G" + g
                elif self.arcs and g in ("17", "18", "19"):
                    state["plane"] = g
                elif g not in self.g_codes:
                    raise ValueError(f"unsupported G{value}")
            elif letter == "M" and (value.lstrip("0") or "0") not in self.m_codes:
                raise ValueError(f"unsupported M{value}")
            elif letter == "F":
                state["F"] = float(value)
        if moved and state["G"] is None:
            raise ValueError("a move before any G0/G1")
        if state["IJK"] and not (moved and state["G"] in ("G2", "G3")):
            raise ValueError("centre words I/J/K without an arc move")
        return moved


_WORD = re.compile(r"([A-Z])([+-]?(?:\d+\.?\d*|\.\d+))")
_PARENS = re.compile(r"\([^()]*\)")
