"""APT CL source of a toolpath (the file a machinist's post-processor reads).

Statements (``toolpath_formulas.md``, "Files a machinist reads"): ``PARTNO``, ``$$`` comments,
``UNITS/MM``, ``CUTTER/D,r``, ``MULTAX/ON`` then ``GOTO/x,y,z,i,j,k`` (tool tip and unit tool
axis), ``FEDRAT/v,MMPM``, ``RAPID``, ``FINI``. Every line is at most 72 columns; a longer
statement is continued with ``$`` on the next line.
"""

from __future__ import annotations

import numpy as np

MAX_COLUMNS = 72


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


def goto(tip: np.ndarray, axis: np.ndarray) -> list[str]:
    """``GOTO/x,y,z,i,j,k`` statements for tool tips ``(m, 3)`` and unit axes ``(m, 3)``."""
    out = []
    for (x, y, z), (i, j, k) in zip(np.asarray(tip, float), np.asarray(axis, float)):
        out += _fit(f"GOTO/{x:.4f},{y:.4f},{z:.4f},{i:.6f},{j:.6f},{k:.6f}")
    return out


def apt_program(
    tip: np.ndarray, axis: np.ndarray, pass_index: np.ndarray, *, diameter: float, corner_radius: float,
    feed_rate: float, part: str = "EVOPLAN", comments: list[str] | None = None, clearance: float = 10.0,
) -> str:
    """The whole CL file: approach above the first point, the passes in order, retract, ``FINI``.

    ``tip``/``axis``: (m, 3) tool tip and unit tool axis in machining order; ``pass_index``:
    (m,) the pass of each point (a ``$$ PASS k`` comment marks where each one starts).
    """
    tip, axis, pass_index = np.asarray(tip, float), np.asarray(axis, float), np.asarray(pass_index)
    if tip.ndim != 2 or tip.shape[1] != 3 or axis.shape != tip.shape or len(pass_index) != len(tip):
        raise ValueError("tip and axis must be (m, 3) and pass_index (m,)")
    if len(tip) == 0:
        raise ValueError("an empty toolpath has no APT program")
    lines = _fit(f"PARTNO/{part.upper()[:60]}")
    for c in comments or []:
        lines += _fit(f"$$ {c}"[:MAX_COLUMNS])
    lines += ["UNITS/MM", *_fit(f"CUTTER/{diameter:.4f},{corner_radius:.4f}"), "MULTAX/ON"]
    lines += ["RAPID", *goto(tip[:1] + clearance * axis[:1], axis[:1])]
    lines += _fit(f"FEDRAT/{feed_rate:.4f},MMPM")
    starts = np.flatnonzero(np.r_[True, pass_index[1:] != pass_index[:-1]])
    bounds = np.r_[starts, len(tip)]
    for a, b in zip(bounds[:-1], bounds[1:]):
        lines.append(f"$$ PASS {int(pass_index[a])}")
        lines += goto(tip[a:b], axis[a:b])
    lines += ["RAPID", *goto(tip[-1:] + clearance * axis[-1:], axis[-1:]), "FINI"]
    return "\n".join(lines) + "\n"
