"""Reading an APT CL file (ours or another CAM system's) back into a toolpath.

Syntax handled: a statement is ``WORD`` or ``WORD/arg,arg,...``; a line ending in a single
``$`` continues on the next line; ``$$`` starts a comment (to the end of the line); keywords
are case-insensitive; blank lines are skipped; reading stops at ``FINI``.

Statements with meaning here:

- ``GOTO/x,y,z[,i,j,k]``: a point (tool point, axis normalised). Without i,j,k the axis is the
  one set by ``TLAXIS/i,j,k`` (default 0,0,1).
- ``GODLTA/dx,dy,dz`` (a point at an offset from the last one) or ``GODLTA/d`` (``d`` along the
  current axis).
- ``FROM/x,y,z[,i,j,k]``: where the tool starts (``start``; not a point of the path).
- ``RAPID``: the next motion only is a rapid.
- ``FEDRAT/v[,MMPM|IPM]`` or ``FEDRAT/MMPM,v``: the feed of the following moves (mm/min).
- ``CUTTER/d[,r[,...]]``: diameter and corner radius (the 7-parameter ``CUTTER/d,r,e,f,a,b,h``
  form too). A cutting (non-rapid) ``GOTO`` before any ``CUTTER`` is an error.
- ``UNITS/MM`` or ``UNITS/INCHES`` (lengths after it are converted to mm); ``MULTAX[/ON|OFF]``.
- ``PARTNO``, ``LOADTL/n``, ``SPINDL/n[,RPM][,CLW|CCLW]`` or ``SPINDL/OFF``,
  ``COOLNT/ON|FLOOD|MIST|AIR|OFF`` are recorded.
- ``$$ PASS k`` / ``$$ ZONE z PASS k`` comments open a new section; ``$$ TOOLPOINT TIP|CENTRE``
  (written by ``apt_write``) states what point a ``GOTO`` gives.

Other post words (``PPRINT``, ``INSERT``, ``INTOL``, ``CUTCOM``, ``STOP``, ...) are accepted and
ignored; any other word, a bad number, a NaN/inf value, a zero axis, or a file without a
``GOTO`` raises ``AptError`` with one line ``LINE n: what is wrong``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

INCH = 25.4
IGNORED = frozenset("""PPRINT INSERT INTOL OUTTOL TOLER CUTCOM STOP OPSTOP END SELCTL TOOLNO CLEARP
    CLRSRF RETRCT DELAY OPSKIP SEQNO MACHIN MODE ORIGIN TLON TLOFPS TLLFT TLRGT AUTOPS NOPOST
    PREFUN AUXFUN ROTABL ROTHED DISPLY PITCH THREAD CYCLE HEAD TURRET LINTOL TITLES PLABEL
    CALSUB CAMERA OPTION PPLOT PRINT PUNCH REWIND SAFETY TRACUT TMARK DRESS LETTER MCHTOL
    MCHFIN LEADER POSMAP PPFUN ROTATE CHECK COUPLE INDEX TABLE SET RESET ON OFF LOAD UNLOAD
    OPERATION_NAME TPRINT""".split())
SECTION = re.compile(r"^(?:ZONE\s+\S+\s+)?PASS\s+\S+", re.I)
TOOLPOINT = re.compile(r"^TOOLPOINT\s+(TIP|CENTRE|CENTER)\b", re.I)
STATEMENT = re.compile(r"^\s*([A-Za-z][A-Za-z0-9_]*)\s*(?:/(.*))?$")


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
    diameter: float
    corner_radius: float
    multax: bool
    tip_is_centre: bool
    part: str = ""
    tool_number: int | None = None
    spindle_rpm: float | None = None
    coolant: str | None = None
    start: np.ndarray | None = None   # FROM point

    def __len__(self) -> int:
        return len(self.tip)


def _statements(text: str):
    """(first line number, statement text, comment text or None) with continuations joined."""
    pending, first = "", 0
    for n, raw in enumerate(text.splitlines(), 1):
        code, sep, comment = raw.partition("$$")
        code = code.strip()
        if not code:
            if sep:
                yield n, "", comment.strip()
            continue
        if not pending:
            first = n
        if code.endswith("$"):
            pending += code[:-1]
            continue
        yield first, pending + code, None
        pending = ""
    if pending:
        yield first, pending, None


def _numbers(args: list[str], line: int, scale: float = 1.0) -> list[float]:
    out = []
    for a in args:
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
        self.cutter: tuple[float, float] | None = None
        self.info: dict = {"part": "", "tool_number": None, "spindle_rpm": None, "coolant": None, "start": None}

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
            self.point(line, [c * self.scale for c in v[:3]], v[3:] if n == 6 else None)
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
            if v[0] <= 0 or (n > 1 and not 0 <= v[1] <= v[0] / 2):
                raise AptError(line, "CUTTER needs d > 0 and 0 <= r <= d/2")
            self.cutter = (v[0], v[1] if n > 1 else 0.0)
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
            if args and args[0].upper() not in ("OFF", "ON", "LOCK", "ORIENT"):
                self.info["spindle_rpm"] = _numbers(args[:1], line)[0]
        elif word == "COOLNT":
            self.info["coolant"] = args[0].upper() if args else "ON"
        elif word == "FINI":
            return False
        elif word not in IGNORED:
            raise AptError(line, f"unknown statement {word}")
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
        m = STATEMENT.match(code)
        if not m:
            raise AptError(line, f"not an APT statement: {code[:40]!r}")
        args = [a.strip() for a in m.group(2).split(",")] if m.group(2) is not None else []
        if not r.statement(line, m.group(1).upper(), args):
            break
    if not r.tip:
        raise AptError(last or 1, "no GOTO: the file holds no toolpath")
    cutter = r.cutter or (math.nan, math.nan)
    return AptToolpath(
        tip=np.array(r.tip, float), axis=np.array(r.axis, float), rapid=np.array(r.rapid, bool),
        feed=np.array(r.feed, float), section=np.array(r.section, int), sections=tuple(r.sections),
        diameter=cutter[0], corner_radius=cutter[1], multax=r.multax, tip_is_centre=r.centre, **r.info)
