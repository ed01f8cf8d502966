"""Cutters (flat-end, ball-end, toroidal) and the tool database.

A cutter is its diameter D and corner radius r: r = 0 flat-end, r = D/2 ball-end,
0 < r < D/2 toroidal (bull-nose). A database is an ordered list of cutters with unique ids;
the optimizer's tool gene is an INDEX into it (0 .. n-1), reported as the tool's id.

Default database: Fountas et al. (Experimental validation) used nine tools, "three sets of
flat-end, ball-end and toroidal tools; having 8 mm, 12 mm and 16 mm each", and its Table 2
names tool 6 as "phi16 Rc3". The only type-major numbering (1-based, diameters ascending)
in which tool 6 is a 16 mm toroidal cutter with Rc 3 is flat, toroidal, ball:

    id  type      D   r        id  type      D   r        id  type   D   r
    1   flat      8   0        4   toroidal  8   1        7   ball   8   4
    2   flat     12   0        5   toroidal 12   2        8   ball  12   6
    3   flat     16   0        6   toroidal 16   3        9   ball  16   8

The toroidal corner radii 1 and 2 mm are our choice (common catalogue sizes; the paper gives
only the 16 mm tool's Rc 3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .checks import number

__all__ = ["Tool", "ToolDatabase", "DEFAULT_TOOLS", "parse_tools"]

_TYPES = ("flat", "ball", "toroidal")


@dataclass(frozen=True)
class Tool:
    """One cutter: id, diameter D (mm), corner radius r (mm), type (derived, checked)."""

    id: int
    diameter: float
    corner_radius: float
    type: str
    name: str = ""

    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    def label(self) -> str:
        return self.name or f"{self.type} D{self.diameter:g} r{self.corner_radius:g}"


DEFAULT_TOOLS = [
    {"id": 1, "type": "flat", "diameter": 8, "corner_radius": 0},
    {"id": 2, "type": "flat", "diameter": 12, "corner_radius": 0},
    {"id": 3, "type": "flat", "diameter": 16, "corner_radius": 0},
    {"id": 4, "type": "toroidal", "diameter": 8, "corner_radius": 1},
    {"id": 5, "type": "toroidal", "diameter": 12, "corner_radius": 2},
    {"id": 6, "type": "toroidal", "diameter": 16, "corner_radius": 3},
    {"id": 7, "type": "ball", "diameter": 8, "corner_radius": 4},
    {"id": 8, "type": "ball", "diameter": 12, "corner_radius": 6},
    {"id": 9, "type": "ball", "diameter": 16, "corner_radius": 8},
]


class ToolDatabase:
    """Ordered cutters; array views ``R``, ``r``, ``ids`` for vectorized lookups by index."""

    def __init__(self, tools: list[Tool]):
        self.tools = list(tools)
        self.ids = np.array([t.id for t in self.tools], dtype=int)
        self.R = np.array([t.radius for t in self.tools], dtype=float)
        self.r = np.array([t.corner_radius for t in self.tools], dtype=float)
        self.kind = np.array([_TYPES.index(t.type) for t in self.tools], dtype=int)

    def __len__(self) -> int:
        return len(self.tools)

    def index_of(self, tool_id) -> int:
        """Index of the tool with this id; ValueError naming ``tool`` if absent."""
        hits = np.flatnonzero(self.ids == int(tool_id))
        if len(hits) == 0:
            raise ValueError(f"params.tool: no tool with id {tool_id} "
                             f"(ids: {', '.join(map(str, self.ids))})")
        return int(hits[0])


def parse_tools(spec=None, key: str = "tools") -> ToolDatabase:
    """Build a database from plain data (a list of mappings); None gives the default nine.

    Each entry: ``diameter`` (> 0), ``corner_radius`` (0 <= r <= D/2), optional ``id``
    (default: position + 1), ``type`` (flat/ball/toroidal; checked against r when given),
    ``name``. Errors are one-line ValueErrors starting with the key path, e.g.
    ``tools[2].corner_radius: 9 exceeds the tool radius 8``.
    """
    if spec is None:
        spec = DEFAULT_TOOLS
    if not isinstance(spec, (list, tuple)) or len(spec) == 0:
        raise ValueError(f"{key}: expected a non-empty list of tools, got {spec!r}")
    tools = []
    for i, item in enumerate(spec):
        k = f"{key}[{i}]"
        if not isinstance(item, dict):
            raise ValueError(f"{k}: expected a mapping, got {item!r}")
        unknown = set(item) - {"id", "type", "diameter", "corner_radius", "name"}
        if unknown:
            raise ValueError(f"{k}: unknown key(s) {', '.join(sorted(unknown))}")
        if "diameter" not in item:
            raise ValueError(f"{k}.diameter: missing")
        d = number(item["diameter"], f"{k}.diameter")
        if d <= 0:
            raise ValueError(f"{k}.diameter: must be > 0, got {d:g}")
        kind = item.get("type")
        default_r = {"flat": 0.0, "ball": d / 2}.get(kind)
        if "corner_radius" not in item and default_r is None:
            raise ValueError(f"{k}.corner_radius: missing")
        r = number(item.get("corner_radius", default_r), f"{k}.corner_radius")
        if r < 0:
            raise ValueError(f"{k}.corner_radius: must be >= 0, got {r:g}")
        if r > d / 2 + 1e-12:
            raise ValueError(f"{k}.corner_radius: {r:g} exceeds the tool radius {d / 2:g}")
        derived = "flat" if r == 0 else ("ball" if abs(r - d / 2) <= 1e-12 else "toroidal")
        if kind is not None and kind != derived:
            if kind not in _TYPES:
                raise ValueError(f"{k}.type: expected one of {', '.join(_TYPES)}, got {kind!r}")
            raise ValueError(f"{k}.type: {kind!r} does not match D {d:g}, r {r:g} "
                             f"(that is a {derived} tool)")
        tid = item.get("id", i + 1)
        if isinstance(tid, bool) or not isinstance(tid, (int, np.integer)):
            raise ValueError(f"{k}.id: expected an integer, got {tid!r}")
        tools.append(Tool(int(tid), d, min(r, d / 2), derived, str(item.get("name", ""))))
    ids = [t.id for t in tools]
    dup = sorted({x for x in ids if ids.count(x) > 1})
    if dup:
        raise ValueError(f"{key}: duplicate tool id(s) {', '.join(map(str, dup))}")
    return ToolDatabase(tools)
