"""APT CL source of a toolpath (the file a machinist's post-processor reads).

Statements written, in order: ``PARTNO``, ``$$`` comments, ``$$ TOOLPOINT TIP`` (or
``CENTRE``), ``UNITS/MM``, ``LOADTL/n``, ``CUTTER/D,r``, ``SPINDL/n,RPM,CLW``, ``COOLNT/ON``,
``MULTAX/ON`` then ``GOTO/x,y,z,i,j,k`` (tool point and unit tool axis), ``FEDRAT/v,MMPM``,
``RAPID``, ``$$ PASS k`` at the start of each pass (or the section's name, e.g.
``$$ ZONE z PASS k``), ``COOLNT/OFF``, ``SPINDL/OFF``, ``FINI``.

Tool point convention: APT itself has no statement saying which point of the cutter a
``GOTO`` gives. evoplan states it in a comment line ``$$ TOOLPOINT TIP`` (the point on the tool
axis at the end of the cutter, the usual CL point) or ``$$ TOOLPOINT CENTRE`` (the centre of
the ball or of the torus' tube circle on the axis). ``apt_read.read_apt`` reads the same line;
a file without it is taken as TIP.

Motion: a rapid to ``clearance`` mm above the first point along its axis, the plunge to the
first point at ``plunge_feed``, the passes at ``feed_rate``, a rapid retract of ``clearance``
above the last point (a path in separate sections, ``Toolpath.from_sections``: a retract and
an approach between sections). Every line is at most 72 columns; a longer statement is
continued with ``$`` on the next line.
"""

from __future__ import annotations

import textwrap

import numpy as np

from ..cutters import Cutter
from .toolpath import Tool, Toolpath

MAX_COLUMNS = 72
COOLANTS = ("ON", "FLOOD", "MIST", "AIR", "OFF")


def _fit(statement: str) -> list[str]:
    """One statement as lines of at most 72 columns, split after a comma with ``$`` continuation."""
    lines = []
    while len(statement) > MAX_COLUMNS:
        cut = statement.rfind(",", 0, MAX_COLUMNS - 1) + 1
        if cut <= 0:
            raise ValueError(f"APT statement cannot be split into {MAX_COLUMNS} columns: {statement!r}")
        lines.append(statement[:cut] + "$")
        statement = statement[cut:]
    return lines + [statement]


def goto(tip: np.ndarray, axis: np.ndarray | None = None) -> list[str]:
    """``GOTO/x,y,z,i,j,k`` statements for points ``(m, 3)`` and unit axes ``(m, 3)``;
    ``GOTO/x,y,z`` when ``axis`` is None (3-axis: the axis set by ``TLAXIS``)."""
    tip = np.asarray(tip, float)
    if axis is None:
        return [s for x, y, z in tip for s in _fit(f"GOTO/{x:.4f},{y:.4f},{z:.4f}")]
    return [s for (x, y, z), (i, j, k) in zip(tip, np.asarray(axis, float))
            for s in _fit(f"GOTO/{x:.4f},{y:.4f},{z:.4f},{i:.6f},{j:.6f},{k:.6f}")]


def header(*, cutter: Cutter, part: str = "EVOPLAN", comments: list[str] | None = None,
           tool_number: int = 1, spindle_rpm: float | None = None, coolant: str = "ON",
           tip_is_centre: bool = False, multax: bool = True) -> list[str]:
    """The statements before the first motion: part, comments, tool point, units, tool, spindle,
    coolant, and ``MULTAX/ON`` (5-axis) or ``TLAXIS/0,0,1`` (3-axis)."""
    if coolant.upper() not in COOLANTS:
        raise ValueError(f"coolant must be one of {', '.join(COOLANTS)}")
    lines = _fit(f"PARTNO/{part.upper()[:60]}")
    for c in comments or []:  # split between words, never cut: "$$ " + 69 columns
        lines += [f"$$ {part}" for part in textwrap.wrap(c, MAX_COLUMNS - 3) or [""]]
    lines += [f"$$ TOOLPOINT {'CENTRE' if tip_is_centre else 'TIP'}", "UNITS/MM", f"LOADTL/{int(tool_number)}"]
    lines += _fit(cutter.apt_cutter())
    if spindle_rpm:
        lines.append(f"SPINDL/{spindle_rpm:.0f},RPM,CLW")
    lines.append(f"COOLNT/{coolant.upper()}")
    lines.append("MULTAX/ON" if multax else "TLAXIS/0,0,1")
    return lines


def footer() -> list[str]:
    """Coolant and spindle off, ``FINI``."""
    return ["COOLNT/OFF", "SPINDL/OFF", "FINI"]


def apt_toolpath(tp: Toolpath, *, part: str = "EVOPLAN", coolant: str = "ON", tip_is_centre: bool = False) -> str:
    """The CL file of one operation (``toolpath.Toolpath``): header, the moves with ``RAPID``
    before each rapid and a ``FEDRAT`` wherever the feed changes (plunge or cutting), a
    ``$$ <label> k`` comment (or the section's name) where each section starts, footer."""
    multax = tp.multi_axis
    lines = header(cutter=tp.tool.cutter, part=part,
                   comments=tp.comments, tool_number=tp.tool.number, spindle_rpm=tp.tool.spindle_rpm,
                   coolant=coolant, tip_is_centre=tip_is_centre, multax=multax)
    feed, section = None, -1
    for n in range(len(tp.tip)):
        if tp.section[n] != section and tp.section[n] >= 0:
            lines.append(f"$$ {tp.section_name(tp.section[n])}")
        section = tp.section[n]
        if tp.rapid[n]:
            lines.append("RAPID")
        else:
            want = tp.plunge_feed if tp.plunge[n] else tp.feed
            if want != feed:
                lines += _fit(f"FEDRAT/{want:.4f},MMPM")
                feed = want
        lines += goto(tp.tip[n:n + 1], tp.axis[n:n + 1] if multax else None)
    return "\n".join(lines + footer()) + "\n"


def apt_plan(path, tool: Tool, *, part: str = "EVOPLAN TOOLPATH", comments: list[str] | None = None) -> str:
    """The CL file of a plan's CL path (``clpath.CLPath``, as the machine runs it) cut by
    ``tool``: each section entered and left as ``Toolpath.from_sections`` does, at the path's
    ``feed_rate``, opened by ``$$ ZONE z PASS k``."""
    starts = np.flatnonzero(np.r_[True, np.diff(path.section) != 0])
    names = {int(path.section[i]): f"ZONE {path.zone[i]} PASS {path.pass_index[i]}" for i in starts}
    tp = Toolpath.from_sections("finish", tool, path.tip, path.axis, path.section, feed=path.feed_rate,
                                comments=comments, section_names=names)
    return apt_toolpath(tp, part=part)


def apt_program(
    tip: np.ndarray, axis: np.ndarray, pass_index: np.ndarray, *, cutter: Cutter,
    feed_rate: float, part: str = "EVOPLAN", comments: list[str] | None = None, clearance: float = 10.0,
    plunge_feed: float | None = None, tool_number: int = 1, spindle_rpm: float | None = None,
    coolant: str = "ON", tip_is_centre: bool = False,
) -> str:
    """The whole CL file of a finishing toolpath given as passes (``Toolpath.from_passes``):
    approach above the first point, plunge, the passes in order, retract.

    ``tip``/``axis``: (m, 3) tool point and unit tool axis in machining order; ``pass_index``:
    (m,) the pass of each point (a ``$$ PASS k`` comment marks where each one starts).
    ``plunge_feed``: feed of the move down to the first point (default: half ``feed_rate``).
    """
    tool = Tool(tool_number, cutter, spindle_rpm)
    tp = Toolpath.from_passes("finish", tool, tip, axis, pass_index, feed=feed_rate, plunge_feed=plunge_feed,
                              clearance=clearance, comments=comments)
    return apt_toolpath(tp, part=part, coolant=coolant, tip_is_centre=tip_is_centre)
