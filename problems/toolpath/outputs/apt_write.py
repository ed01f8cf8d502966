"""APT CL source of a toolpath (the file a machinist's post-processor reads).

Statements written, in order: ``PARTNO``, ``$$`` comments, ``$$ TOOLPOINT TIP`` (or
``CENTRE``), ``UNITS/MM``, ``LOADTL/n``, ``CUTTER/D,r``, ``SPINDL/n,RPM,CLW``, ``COOLNT/ON``,
``MULTAX/ON`` then ``GOTO/x,y,z,i,j,k`` (tool point and unit tool axis), ``FEDRAT/v,MMPM``,
``RAPID``, ``$$ PASS k`` at the start of each pass, ``COOLNT/OFF``, ``SPINDL/OFF``, ``FINI``.

Tool point convention: APT itself has no statement saying which point of the cutter a
``GOTO`` gives. evoplan states it in a comment line ``$$ TOOLPOINT TIP`` (the point on the tool
axis at the end of the cutter, the usual CL point) or ``$$ TOOLPOINT CENTRE`` (the centre of
the ball or of the torus' tube circle on the axis). ``apt_read.read_apt`` reads the same line;
a file without it is taken as TIP.

Motion: a rapid to ``clearance`` mm above the first point along its axis, the plunge to the
first point at ``plunge_feed``, the passes at ``feed_rate``, a rapid retract of ``clearance``
above the last point. Every line is at most 72 columns; a longer statement is continued with
``$`` on the next line.
"""

from __future__ import annotations

import numpy as np

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


def header(*, diameter: float, corner_radius: float, part: str = "EVOPLAN", comments: list[str] | None = None,
           tool_number: int = 1, spindle_rpm: float | None = None, coolant: str = "ON",
           tip_is_centre: bool = False, multax: bool = True) -> list[str]:
    """The statements before the first motion: part, comments, tool point, units, tool, spindle,
    coolant, and ``MULTAX/ON`` (5-axis) or ``TLAXIS/0,0,1`` (3-axis)."""
    if coolant.upper() not in COOLANTS:
        raise ValueError(f"coolant must be one of {', '.join(COOLANTS)}")
    lines = _fit(f"PARTNO/{part.upper()[:60]}")
    for c in comments or []:
        lines += _fit(f"$$ {c}"[:MAX_COLUMNS])
    lines += [f"$$ TOOLPOINT {'CENTRE' if tip_is_centre else 'TIP'}", "UNITS/MM", f"LOADTL/{int(tool_number)}"]
    lines += _fit(f"CUTTER/{diameter:.4f},{corner_radius:.4f}")
    if spindle_rpm is not None:
        lines.append(f"SPINDL/{spindle_rpm:.0f},RPM,CLW")
    lines.append(f"COOLNT/{coolant.upper()}")
    lines.append("MULTAX/ON" if multax else "TLAXIS/0,0,1")
    return lines


def footer() -> list[str]:
    """Coolant and spindle off, ``FINI``."""
    return ["COOLNT/OFF", "SPINDL/OFF", "FINI"]


def apt_program(
    tip: np.ndarray, axis: np.ndarray, pass_index: np.ndarray, *, diameter: float, corner_radius: float,
    feed_rate: float, part: str = "EVOPLAN", comments: list[str] | None = None, clearance: float = 10.0,
    plunge_feed: float | None = None, tool_number: int = 1, spindle_rpm: float | None = None,
    coolant: str = "ON", tip_is_centre: bool = False,
) -> str:
    """The whole CL file: approach above the first point, plunge, the passes in order, retract.

    ``tip``/``axis``: (m, 3) tool point and unit tool axis in machining order; ``pass_index``:
    (m,) the pass of each point (a ``$$ PASS k`` comment marks where each one starts).
    ``plunge_feed``: feed of the move down to the first point (default: half ``feed_rate``).
    """
    tip, axis, pass_index = np.asarray(tip, float), np.asarray(axis, float), np.asarray(pass_index)
    if tip.ndim != 2 or tip.shape[1] != 3 or axis.shape != tip.shape or len(pass_index) != len(tip):
        raise ValueError("tip and axis must be (m, 3) and pass_index (m,)")
    if len(tip) == 0:
        raise ValueError("an empty toolpath has no APT program")
    plunge = 0.5 * feed_rate if plunge_feed is None else plunge_feed
    lines = header(diameter=diameter, corner_radius=corner_radius, part=part, comments=comments,
                   tool_number=tool_number, spindle_rpm=spindle_rpm, coolant=coolant, tip_is_centre=tip_is_centre)
    lines += ["RAPID", *goto(tip[:1] + clearance * axis[:1], axis[:1])]
    lines += _fit(f"FEDRAT/{plunge:.4f},MMPM")
    starts = np.flatnonzero(np.r_[True, pass_index[1:] != pass_index[:-1]])
    bounds = np.r_[starts, len(tip)]
    for n, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
        lines.append(f"$$ PASS {int(pass_index[a])}")
        if n == 0:
            lines += goto(tip[:1], axis[:1]) + _fit(f"FEDRAT/{feed_rate:.4f},MMPM")
            a += 1
        lines += goto(tip[a:b], axis[a:b])
    lines += ["RAPID", *goto(tip[-1:] + clearance * axis[-1:], axis[-1:]), *footer()]
    return "\n".join(lines) + "\n"
