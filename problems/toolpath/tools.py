"""The tool database: an ordered list of cutters with unique ids.

A cutter is its diameter D and corner radius r (r = 0 flat-end, r = D/2 ball-end,
0 < r < D/2 toroidal); its shape is the registered :class:`~.cutters.Cutter` that
:func:`~.cutters.make_cutter` infers from (D, r). The optimizer's tool gene is an INDEX into
the database (0 .. n-1), reported as the tool's id.

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

from dataclasses import dataclass, field

import numpy as np

from .checks import number
from .cutters import Cutter, make_cutter

__all__ = ["Tool", "ToolDatabase", "DEFAULT_TOOLS", "parse_tools"]


@dataclass(frozen=True)
class Tool:
    """One database entry: id, diameter D (mm), corner radius r (mm), type (the cutter's
    kind), name, and its :class:`~.cutters.Cutter`."""

    id: int
    diameter: float
    corner_radius: float
    type: str
    name: str = ""
    cutter: Cutter | None = field(default=None, compare=False, repr=False)
    feed: float | None = None          # mm/min (the kinematic machining time and the NC program)
    plunge_feed: float | None = None   # mm/min
    spindle: float | None = None       # rpm

    def __post_init__(self):
        if self.cutter is None:
            object.__setattr__(self, "cutter", make_cutter(self.diameter, self.corner_radius,
                                                           self.type))

    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    def label(self) -> str:
        return self.name or self.cutter.label()


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
    """Ordered tools; their cutters (:meth:`cutter`, ``cutters``) and array views ``R``
    (radius), ``r`` (corner radius), ``ids`` for vectorized lookups by index."""

    def __init__(self, tools: list[Tool]):
        self.tools = list(tools)
        self.cutters = [t.cutter for t in self.tools]
        self.ids = np.array([t.id for t in self.tools], dtype=int)
        self.R = np.array([c.radius for c in self.cutters], dtype=float)
        self.r = np.array([c.corner_radius for c in self.cutters], dtype=float)

    def __len__(self) -> int:
        return len(self.tools)

    def cutter(self, index) -> Cutter:
        """The cutter of the tool at ``index`` (0 .. n-1)."""
        return self.cutters[int(index)]

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
    (default: position + 1), ``type`` (flat/ball/toroidal/tapered_ball; checked against r
    when given), ``taper_angle`` (degrees: the half-angle of a tapered ball's cone),
    ``name``, and the cutting data ``feed`` (mm/min), ``plunge_feed`` (mm/min), ``spindle``
(rpm): an entry with any of them needs its ``feed``. The shape comes from :func:`~.cutters.make_cutter` (a registered name or
    alias is accepted as ``type``). Errors are one-line ValueErrors starting with the key
    path, e.g.
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
        unknown = set(item) - {"id", "type", "diameter", "corner_radius", "taper_angle", "name",
                               "feed", "plunge_feed", "spindle"}
        if unknown:
            raise ValueError(f"{k}: unknown key(s) {', '.join(sorted(unknown))}")
        if "diameter" not in item:
            raise ValueError(f"{k}.diameter: missing")
        d = number(item["diameter"], f"{k}.diameter")
        if d <= 0:
            raise ValueError(f"{k}.diameter: must be > 0, got {d:g}")
        r = None
        if "corner_radius" in item:
            r = number(item["corner_radius"], f"{k}.corner_radius")
            if r < 0:
                raise ValueError(f"{k}.corner_radius: must be >= 0, got {r:g}")
            if r > d / 2 + 1e-12:
                raise ValueError(f"{k}.corner_radius: {r:g} exceeds the tool radius {d / 2:g}")
        # the shape inferred, a given type checked (a tapered ball: its taper_angle, degrees)
        cutter = make_cutter(d, r, item.get("type"), key=k, taper_angle=item.get("taper_angle"))
        tid = item.get("id", i + 1)
        if isinstance(tid, bool) or not isinstance(tid, (int, np.integer)):
            raise ValueError(f"{k}.id: expected an integer, got {tid!r}")
        rates = {}
        for rk in ("feed", "plunge_feed", "spindle"):
            if rk in item:
                rates[rk] = number(item[rk], f"{k}.{rk}")
                if rates[rk] <= 0:
                    raise ValueError(f"{k}.{rk}: must be > 0, got {rates[rk]:g}")
        if rates and "feed" not in rates:
            raise ValueError(f"{k}.feed: missing (an entry with {', '.join(sorted(rates))} needs its feed, mm/min)")
        tools.append(Tool(int(tid), d, cutter.corner_radius, cutter.kind,
                          str(item.get("name", "")), cutter, **rates))
    ids = [t.id for t in tools]
    dup = sorted({x for x in ids if ids.count(x) > 1})
    if dup:
        raise ValueError(f"{key}: duplicate tool id(s) {', '.join(map(str, dup))}")
    return ToolDatabase(tools)
