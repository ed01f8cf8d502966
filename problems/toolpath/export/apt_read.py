"""Reading an APT CL file (ours or another CAM system's) back into a toolpath.

Syntax handled: a statement is ``WORD`` or ``WORD/arg,arg,...``; a line ending in a single
``$`` continues on the next line; ``$$`` starts a comment (to the end of the line, or on the
next lines while a comment-only line ends in ``$``: Creo's ``$$-> CSYS / ...``); keywords
are case-insensitive; blank lines are skipped; reading stops at ``FINI``.

Statements with meaning here:

- ``GOTO/x,y,z[,i,j,k]``: a point (tool point, axis normalised). Without i,j,k the axis is the
  one set by ``TLAXIS/i,j,k`` (default 0,0,1).
- ``GODLTA/dx,dy,dz`` (a point at an offset from the last one) or ``GODLTA/d`` (``d`` along the
  current axis).
- ``FROM/x,y,z[,i,j,k]``: where the tool starts (``start``; not a point of the path).
- ``RAPID``: the next motion only is a rapid.
- ``FEDRAT/v[,MMPM|IPM]`` or ``FEDRAT/MMPM,v``: the feed of the following moves (mm/min).
- ``CUTTER/d[,r[,...]]``: the cutter, diameter and corner radius, or the 7-parameter
  ``CUTTER/d,r,e,f,a,b,h`` form (the registered shape that reads it: ``cutters.cutter_from_apt``;
  a tapered ball as ``cutters/tapered.py`` writes it). A cutting (non-rapid) ``GOTO`` before
  any ``CUTTER`` is an error.
- ``UNITS/MM`` or ``UNITS/INCHES`` (lengths after it are converted to mm); ``MULTAX[/ON|OFF]``.
- ``PARTNO``, ``LOADTL/n``, ``SPINDL/n[,RPM][,CLW|CCLW]`` or ``SPINDL/OFF``,
  ``COOLNT/ON|FLOOD|MIST|AIR|OFF`` are recorded.
- ``$$ PASS k`` / ``$$ ZONE z PASS k`` comments open a new section; ``$$ TOOLPOINT TIP|CENTRE``
  (written by ``apt_write``) states what point a ``GOTO`` gives.

- ``CIRCLE/xc,yc,zc,i,j,k,r[,...]`` then ``GOTO/end``: an arc about the axis (i, j, k)
  (counter-clockwise looking down it, the APT convention) from the last point to the end
  point, written as points within the chord tolerance (``INTOL``/``OUTTOL``/``TOLER``, or
  ``chord_tol``: 0.01 mm); the start and end must lie at r from the axis.
- ``GOHOME``: a rapid back to the ``FROM`` point (listed as ignored without one).
- ``TLDATA/MILL,d,r[,...]`` (NX) as ``CUTTER/d,r``; ``SELECT/TOOL,n`` and ``LOAD/TOOL,n`` as
  ``LOADTL/n``; ``SPINDL/RPM,n,CLW`` (Creo) as well as ``SPINDL/n,RPM``.
- Numbers take Fortran ``D`` exponents (``1.5D+00``).

Every other statement that does not move the tool (``PPRINT`` and ``INSERT``, whose free
text follows a space or a slash, ``MSYS/`` (the output frame the
GOTOs are already in), ``PAINT/``, ``INDIRV/``, ``TOOL PATH/``, ``END-OF-PATH``, ``CUTCOM/OFF``, ``TRACUT/NOMORE``,
``REFSYS/NOMORE``, ...) is counted and listed in ``ignored``. A motion statement this reader
does not take (``GOFWD``, ``GOLFT``, ``GORGT``, ``GOBACK``, ``GOUP``, ``GODOWN``, ``GO``,
``MOVARC``, ``PSIS``, ``CYCLE/`` other than ``OFF``), a statement that changes the motion of
what follows (``TRANS``, ``ORIGIN``, ``ROTABL``, ``COPY``, ``INDEX``, ``ROTATE``, ``CUTCOM``,
``RETRCT``, ``TRACUT``, ``REFSYS``, ``ROTHED``, but not their cancels above), a bad number, a NaN/inf value, a zero axis, or a
file without a ``GOTO`` raises ``AptError`` with one line ``LINE n: what is wrong``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..cutters import Cutter, cutter_from_apt, make_cutter

INCH = 25.4
MOTION = frozenset("GOFWD GOLFT GORGT GOBACK GOUP GODOWN GO MOVARC PSIS DNTCUT".split())
# statements that change where the following GOTOs put the tool (a frame, a copy, an offset, a
# retract, a head or table turn); the argument that cancels one is harmless and stays ignored
MOTION_CHANGE = {"TRANS": (), "ORIGIN": (), "ROTABL": (), "COPY": (), "INDEX": (), "ROTATE": (),
                 "CUTCOM": ("OFF",), "RETRCT": (), "TRACUT": ("NOMORE",), "REFSYS": ("NOMORE",),
                 "ROTHED": ()}
SECTION = re.compile(r"^(?:ZONE\s+\S+\s+)?PASS\s+\S+", re.I)
TOOLPOINT = re.compile(r"^TOOLPOINT\s+(TIP|CENTRE|CENTER)\b", re.I)
STATEMENT = re.compile(r"^\s*([A-Za-z][A-Za-z0-9_\- ]*?)\s*(?:/(.*))?$")
TEXT = re.compile(r"^\s*(PPRINT|INSERT)(?:[\s/]|$)", re.I)  # statements whose argument is free text
FORTRAN = re.compile(r"^([+-]?(?:\d+\.?\d*|\.\d+))[dD]([+-]?\d+)$")


class AptError(ValueError):
    """A CL file that cannot be read; the message is one line ``LINE n: what is wrong``."""

    def __init__(self, line: int, message: str):
        super().__init__(f"LINE {line}: {message}")
        self.line = line


@dataclass(frozen=True)
class AptToolpath:
    """A toolpath read from a CL file; per-point arrays in file order (m points)."""

    tip: np.ndarray          # (m, 3) tool point (tip, or centre if tip_is_centre)
    axis: np.ndarray         # (m, 3) unit tool axis
    rapid: np.ndarray        # (m,) bool: the move into this point is a rapid
    feed: np.ndarray         # (m,) feed in force, mm/min (nan before any FEDRAT)
    section: np.ndarray      # (m,) index into ``sections`` (-1 before the first)
    sections: tuple[str, ...]  # the section comments, e.g. "PASS 3"
    cutter: Cutter | None    # the CUTTER/ (or TLDATA/) statement's; None without one
    multax: bool
    tip_is_centre: bool
    part: str = ""
    tool_number: int | None = None
    spindle_rpm: float | None = None
    coolant: str | None = None
    start: np.ndarray | None = None   # FROM point
    ignored: dict | None = None       # statement word -> count of the statements not acted on

    def __len__(self) -> int:
        return len(self.tip)


def _statements(text: str):
    """(first line number, statement text, comment text or None) with continuations joined.

    A comment-only line whose text ends in a single ``$`` (Creo's ``$$-> CSYS / ..., $``)
    continues as comment on the next lines, up to one that does not end in ``$``."""
    pending, first, note = "", 0, None
    for n, raw in enumerate(text.splitlines(), 1):
        if note is not None:  # a continued comment: this line is its text, with or without $$
            body = raw.strip()
            note += " " + (body[2:] if body.startswith("$$") else body).rstrip("$").strip()
            if not _continues(body):
                yield first, "", note.strip()
                note = None
            continue
        code, sep, comment = raw.partition("$$")
        code = code.strip()
        if not code:
            if sep and not pending and _continues(comment.strip()):
                first, note = n, comment.strip()[:-1]
            elif sep:
                yield n, "", comment.strip()
            continue
        if not pending:
            first = n
        if code.endswith("$"):
            pending += code[:-1]
            continue
        yield first, pending + code, None
        pending = ""
    if note is not None:
        yield first, "", note.strip()
    if pending:
        yield first, pending, None


def _continues(text: str) -> bool:
    """The line's text ends in a single ``$`` (``$$`` closes a comment, e.g. ``$$ *** $$``)."""
    return text.endswith("$") and not text.endswith("$$")


def _numbers(args: list[str], line: int, scale: float = 1.0) -> list[float]:
    out = []
    for a in args:
        try:
            v = float(a)  # the common case; FORTRAN's D exponents are never floats, so the same values
        except ValueError:
            a = FORTRAN.sub(r"\1e\2", a.strip())
            try:
                v = float(a)
            except ValueError:
                raise AptError(line, f"not a number: {a!r}") from None
        if not math.isfinite(v):
            raise AptError(line, f"non-finite value {a!r}")
        out.append(v * scale)
    return out


class _Reader:
    def __init__(self):
        self.tip, self.axis, self.rapid, self.feed, self.section = [], [], [], [], []
        self.sections: list[str] = []
        self.scale, self.cur_axis, self.cur_feed = 1.0, (0.0, 0.0, 1.0), math.nan
        self.next_rapid, self.multax, self.centre = False, False, False
        self.cutter: Cutter | None = None
        self.info: dict = {"part": "", "tool_number": None, "spindle_rpm": None, "coolant": None, "start": None,
                           "ignored": {}}
        self.circle: tuple | None = None
        self.chord_tol = 0.01

    def ignore(self, word: str) -> None:
        self.info["ignored"][word] = self.info["ignored"].get(word, 0) + 1

    def arc(self, line: int, end: list[float]) -> None:
        """The points of the pending CIRCLE's arc from the last point to ``end`` (excluded)."""
        (c, ax, r), self.circle = self.circle, None
        if not self.tip:
            raise AptError(line, "CIRCLE before any GOTO")
        c, ax = np.asarray(c), np.asarray(ax)
        p0, p1 = np.asarray(self.tip[-1]), np.asarray(end)
        w0, w1 = p0 - c - np.dot(p0 - c, ax) * ax, p1 - c - np.dot(p1 - c, ax) * ax
        tol = max(self.chord_tol, 1e-3 * r)
        for w in (w0, w1):
            if abs(np.linalg.norm(w) - r) > max(10 * tol, 1e-3):
                raise AptError(line, f"CIRCLE: the arc's end is {np.linalg.norm(w):.4f} from the axis, not r = {r:g}")
        e0 = w0 / np.linalg.norm(w0)
        e1 = np.cross(ax, e0)
        total = math.atan2(np.dot(w1, e1), np.dot(w1, e0)) % (2 * math.pi)
        if total < 1e-9:
            total = 2 * math.pi if np.linalg.norm(p1 - p0) < 1e-9 else total
        dz0, dz1 = np.dot(p0 - c, ax), np.dot(p1 - c, ax)
        step = 2 * math.acos(max(-1.0, 1 - self.chord_tol / r)) if self.chord_tol < r else math.pi / 2
        k = max(1, int(math.ceil(total / step - 1e-12)))
        rapid = self.next_rapid
        for i in range(1, k):
            t = i / k
            a = t * total
            q = c + r * (math.cos(a) * e0 + math.sin(a) * e1) + (dz0 + t * (dz1 - dz0)) * ax
            self.point(line, list(q), None)
            self.next_rapid = rapid

    def comment(self, text: str) -> None:
        if SECTION.match(text):
            self.sections.append(" ".join(text.split()).upper())
        elif m := TOOLPOINT.match(text):
            self.centre = m.group(1).upper() != "TIP"

    def point(self, line: int, xyz: list[float], ijk: list[float] | None) -> None:
        if not self.next_rapid and self.cutter is None:
            raise AptError(line, "cutting GOTO before any CUTTER/ statement")
        self.tip.append(xyz)
        self.axis.append(self.axis_of(line, ijk) if ijk is not None else self.cur_axis)
        self.rapid.append(self.next_rapid)
        self.feed.append(self.cur_feed)
        self.section.append(len(self.sections) - 1)
        self.next_rapid = False

    def axis_of(self, line: int, ijk: list[float]) -> tuple[float, float, float]:
        norm = math.sqrt(sum(c * c for c in ijk))
        if norm < 1e-12:
            raise AptError(line, "zero tool axis")
        return tuple(c / norm for c in ijk)

    def statement(self, line: int, word: str, args: list[str]) -> bool:
        """Apply one statement; False at FINI."""
        n = len(args)
        if word == "GOTO":
            if n not in (3, 6):
                raise AptError(line, f"GOTO needs 3 or 6 values, got {n}")
            v = _numbers(args, line)
            self.multax |= n == 6
            xyz = [c * self.scale for c in v[:3]]
            if self.circle is not None:
                self.arc(line, xyz)
            self.point(line, xyz, v[3:] if n == 6 else None)
        elif word == "CIRCLE":
            if n < 7:
                raise AptError(line, f"CIRCLE needs at least 7 values (centre, axis, radius), got {n}")
            v = _numbers(args[:7], line)
            ax = np.asarray(self.axis_of(line, v[3:6]))
            if v[6] <= 0:
                raise AptError(line, "CIRCLE radius must be > 0")
            self.circle = ([x * self.scale for x in v[:3]], ax, v[6] * self.scale)
        elif word in ("INTOL", "OUTTOL", "TOLER"):
            vals = [abs(x) for x in _numbers([a for a in args if not a.strip().isalpha()], line, self.scale)]
            if vals and max(vals) > 0:
                self.chord_tol = max(vals)
            self.ignore(word)
        elif word == "GOHOME":
            if self.info["start"] is None:
                self.ignore(word)
            else:
                self.next_rapid = True
                self.point(line, list(self.info["start"]), None)
        elif word == "TLDATA":
            kind = args[0].upper() if args else ""
            vals = [a for a in args[1:]]
            if kind != "MILL" or len(vals) < 2:
                raise AptError(line, "TLDATA: expected TLDATA/MILL,diameter,corner radius[,...]")
            d, r = _numbers(vals[:2], line, self.scale)
            if d <= 0 or not 0 <= r <= d / 2:
                raise AptError(line, "TLDATA needs d > 0 and 0 <= r <= d/2")
            self.cutter = make_cutter(d, r, key="TLDATA")
        elif word in ("SELECT", "LOAD") and args and args[0].upper() == "TOOL":
            nums = [a for a in args[1:] if not a.strip().isalpha()]
            self.info["tool_number"] = int(_numbers(nums[:1], line)[0]) if nums else None
        elif word in MOTION:
            raise AptError(line, f"motion statement {word} is not supported (GOTO, GODLTA, CIRCLE, RAPID, GOHOME are)")
        elif word in MOTION_CHANGE and not (args and args[0].upper() in MOTION_CHANGE[word]):
            raise AptError(line, f"{word} changes the motion of what follows and is not understood here "
                                 "(have the CAM system write the moves with it applied)")
        elif word == "CYCLE" and not (args and args[0].upper() == "OFF"):
            raise AptError(line, "CYCLE/ (a canned cycle moves the tool) is not supported")
        elif word == "GODLTA":
            if not self.tip:
                raise AptError(line, "GODLTA before any GOTO")
            if n not in (1, 3):
                raise AptError(line, f"GODLTA needs 1 or 3 values, got {n}")
            v, last, ax = _numbers(args, line, self.scale), self.tip[-1], self.axis[-1]
            d = [v[0] * a for a in ax] if n == 1 else v
            self.point(line, [p + q for p, q in zip(last, d)], list(ax))
        elif word == "FROM":
            if n not in (3, 6):
                raise AptError(line, f"FROM needs 3 or 6 values, got {n}")
            self.info["start"] = np.array(_numbers(args[:3], line, self.scale))
            if n == 6:
                self.cur_axis = self.axis_of(line, _numbers(args[3:], line))
        elif word == "RAPID":
            self.next_rapid = True
        elif word == "FEDRAT":
            self.fedrat(line, args)
        elif word == "CUTTER":
            if not 1 <= n <= 7:
                raise AptError(line, f"CUTTER needs 1 to 7 values, got {n}")
            v = _numbers(args, line, self.scale)
            if n > 4:  # the angles a, b are degrees, not lengths
                v[4:6] = [x / self.scale for x in v[4:6]]
            try:
                self.cutter = cutter_from_apt(v)
            except ValueError as e:
                raise AptError(line, str(e)) from None
        elif word == "TLAXIS":
            if n != 3:
                raise AptError(line, f"TLAXIS needs 3 values, got {n}")
            self.cur_axis = self.axis_of(line, _numbers(args, line))
        elif word == "UNITS":
            unit = args[0].upper() if args else ""
            if unit not in ("MM", "INCHES", "INCH"):
                raise AptError(line, f"unknown UNITS {unit!r}")
            self.scale = 1.0 if unit == "MM" else INCH
        elif word == "MULTAX":
            self.multax = not args or args[0].upper() != "OFF"
        elif word == "PARTNO":
            self.info["part"] = ",".join(args).strip()
        elif word == "LOADTL":
            self.info["tool_number"] = int(_numbers(args[:1], line)[0]) if args else None
        elif word == "SPINDL":
            nums = [a for a in args if not a.strip().isalpha()]
            if nums and not (args and args[0].upper() in ("OFF", "LOCK", "ORIENT")):
                self.info["spindle_rpm"] = _numbers(nums[:1], line)[0]
        elif word == "COOLNT":
            self.info["coolant"] = args[0].upper() if args else "ON"
        elif word == "FINI":
            return False
        else:
            self.ignore(word)
        return True

    def fedrat(self, line: int, args: list[str]) -> None:
        units = [a.upper() for a in args if a.strip().isalpha()]
        values = [a for a in args if not a.strip().isalpha()]
        if len(values) != 1 or any(u not in ("MMPM", "IPM", "MMPR", "IPR") for u in units):
            raise AptError(line, "FEDRAT needs one value and MMPM or IPM")
        if any(u in ("MMPR", "IPR") for u in units):
            raise AptError(line, "feed per revolution is not supported (use MMPM)")
        v = _numbers(values, line)[0]
        if v <= 0:
            raise AptError(line, "FEDRAT must be > 0")
        inch = "IPM" in units or (not units and self.scale != 1.0)
        self.cur_feed = v * (INCH if inch else 1.0)


def read_apt(path: str | Path) -> AptToolpath:
    """The toolpath of an APT CL file (see the module docstring); raises ``AptError``."""
    data = Path(path).read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise AptError(data[:e.start].count(b"\n") + 1, "not UTF-8 text") from None
    r, last = _Reader(), 0
    for line, code, comment in _statements(text):
        last = line
        if comment is not None:
            r.comment(comment)
            continue
        if code.upper().startswith("PARTNO"):
            r.info["part"] = code[6:].lstrip(" /").strip()
            continue
        text_word = TEXT.match(code)
        if text_word:  # PPRINT / INSERT carry free text after a space (or a slash): nothing moves
            r.ignore(text_word.group(1).upper())
            continue
        m = STATEMENT.match(code)
        if not m or (" " in m.group(1).strip() and m.group(2) is None):  # "TOOL PATH/..." needs its slash
            raise AptError(line, f"not an APT statement: {code[:40]!r}")
        args = [a.strip() for a in m.group(2).split(",")] if m.group(2) is not None else []
        if not r.statement(line, m.group(1).upper(), args):
            break
    if not r.tip:
        raise AptError(last or 1, "no GOTO: the file holds no toolpath")
    return AptToolpath(
        tip=np.array(r.tip, float), axis=np.array(r.axis, float), rapid=np.array(r.rapid, bool),
        feed=np.array(r.feed, float), section=np.array(r.section, int), sections=tuple(r.sections),
        cutter=r.cutter, multax=r.multax, tip_is_centre=r.centre, **r.info)
