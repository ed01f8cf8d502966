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
to ``POSTS``.
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
        if abs(tp.tool.corner_radius - 0.5 * tp.tool.diameter) < 1e-9:  # a ball: keep its centre
            tp_tip = tp.tip + tp.tool.corner_radius * (tp.axis - real)
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
    def program(self, tp: Toolpath, name: str = "EVOPLAN") -> str:
        """The whole NC program of one operation."""
        mv = self.moves(tp)
        lines = self.header(tp, name.upper(), mv)
        last: dict[str, str] = {}
        for n in range(len(mv.tip)):
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
        state = {"G": None, "F": np.nan, "X": np.nan, "Y": np.nan, "Z": np.nan, "A0": np.nan, "A1": np.nan}
        tip, ang, rapid, feed = [], [], [], []
        for n, line in enumerate(text.splitlines(), 1):
            try:
                move = self.parse_line(line, state)
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
        axes = {"X": "X", "Y": "Y", "Z": "Z"}
        if self.five_axis:
            axes.update({self.axis_names[0]: "A0", self.axis_names[1]: "A1"})
        for token in code.split():
            if token in self.keywords:
                continue
            m = _WORD.fullmatch(token)
            if not m or (m.group(1) not in self.letters and m.group(1) not in axes):
                raise ValueError(f"unknown word {token!r}")
            letter, value = m.group(1), m.group(2)
            if letter in axes:
                state[axes[letter]] = float(value)
                moved = True
            elif letter == "G":
                g = value.lstrip("0") or "0"
                if g in ("0", "1"):
                    state["G"] = "G" + g
                elif g not in self.g_codes:
                    raise ValueError(f"unsupported G{value}")
            elif letter == "M" and (value.lstrip("0") or "0") not in self.m_codes:
                raise ValueError(f"unsupported M{value}")
            elif letter == "F":
                state["F"] = float(value)
        if moved and state["G"] is None:
            raise ValueError("a move before any G0/G1")
        return moved


_WORD = re.compile(r"([A-Z])([+-]?(?:\d+\.?\d*|\.\d+))")
_PARENS = re.compile(r"\([^()]*\)")
