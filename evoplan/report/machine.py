"""The report of an ``evoplan machine`` folder: each operation's figures (``summary.json``), the
roughing layers, and every operation's path in 3D over the part (``surface.stl``), read from
the operations' APT files (the programs the NC files were posted from)."""

from __future__ import annotations

from pathlib import Path

from .folder import read_json
from .page import Section, note, table

__all__ = ["sections"]

OPERATIONS = ("roughing", "semifinish", "finish")


def sections(folder: Path) -> list[Section]:
    from ..errors import ConfigError
    from ..problems.toolpath.export.apt_read import AptError
    from .paths import read_moves, stl_trace, toolpath_figure

    summary = read_json(folder / "summary.json")
    ops = [op for op in OPERATIONS if isinstance(summary.get(op), dict)]
    out = []
    rows = []
    for op in ops:
        s = summary[op]
        lengths = s.get("lengths_mm", {})
        rows.append({"operation": op, "tool": (s.get("tool") or {}).get("label", ""), "CL points": s.get("points"),
                     "cutting (mm)": lengths.get("cutting"), "plunge (mm)": lengths.get("plunge"),
                     "rapid (mm)": lengths.get("rapid"), "time (min)": s.get("time_min"),
                     "NC lines": s.get("nc_lines"), "NC size (bytes)": s.get("nc_bytes"),
                     "multi-axis": s.get("multi_axis")})
    keys = list(rows[0]) if rows else []
    out.append(Section("Operations", [table(keys, [[r[k] for k in keys] for r in rows]),
                                      note(f"summary.json; post {summary.get('post', '?')}")]))
    layers = (summary.get("roughing") or {}).get("layers") or []
    moves = []
    for op in ops:
        apt = folder / f"{op}.apt"
        if not apt.is_file():
            raise ConfigError(f"{apt}: missing (summary.json lists the {op} operation)")
        try:
            moves.append(read_moves(apt, op))
        except AptError as e:
            raise ConfigError(f"{apt}: {e}") from None
    part = stl_trace(folder / "surface.stl") if (folder / "surface.stl").is_file() else None
    fig, cap = toolpath_figure(moves, part, title="every operation over the part (click the legend to hide one)",
                               name="operations3d")
    out.append(Section("Paths in 3D", [fig, note(cap)]))
    rough = [m for m in moves if m.name == "roughing"]
    if rough:
        items = []
        if layers:
            items.append(table(["layer", "removed (mm³)", "max depth (mm)", "cutting length (mm)",
                                "cutting in air (mm)"],
                               [[r.get("section"), r.get("removed_mm3"), r.get("max_depth"),
                                 r.get("cutting_length"), r.get("air_length")] for r in layers]))
        fig, cap = toolpath_figure(rough, part, title="roughing, coloured by layer", name="layers3d")
        out.append(Section("Roughing layers", [*items, fig, note(cap)]))
    return out
