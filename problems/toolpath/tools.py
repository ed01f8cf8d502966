"""The one tool definition: a registered cutter plus its id and cutting data; the database.

A :class:`Tool` is a :class:`~.cutters.Cutter` (its shape and size) with the id the run file
and the NC program know it by (the APT ``LOADTL`` / G-code ``T`` number), an optional name and
its cutting data (feed, plunge feed, spindle speed). The toolpath problem, the ``zone`` and
``machine`` commands and every export (APT, the posts) hold this one class; a tool's settings
in a run file are validated by ``spec/tools.py``. The optimizer's tool gene is an INDEX into
the :class:`ToolDatabase` (0 .. n-1), reported as the tool's id.

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

from .cutters import Cutter

__all__ = ["Tool", "ToolDatabase", "DEFAULT_TOOLS", "CHOI_TOOLS", "DEFAULT_SPINDLE_RPM"]

#: the spindle speed an NC program gets for a tool without one (rpm)
DEFAULT_SPINDLE_RPM = 6000.0


@dataclass(frozen=True)
class Tool:
    """One tool: ``id`` (the NC tool number), its :class:`~.cutters.Cutter`, ``spindle``
    (rpm; None: the NC program's default, :data:`DEFAULT_SPINDLE_RPM`), ``feed`` and
    ``plunge_feed`` (mm/min; None: the machine's or the operation's), ``name``."""

    id: int
    cutter: Cutter
    spindle: float | None = DEFAULT_SPINDLE_RPM
    feed: float | None = None
    plunge_feed: float | None = None
    name: str = ""

    def __post_init__(self):
        if not isinstance(self.cutter, Cutter):
            raise ValueError(f"tool {self.id}: the cutter must be a Cutter, got {self.cutter!r}")

    @property
    def number(self) -> int:
        """The NC tool number (the id)."""
        return self.id

    @property
    def spindle_rpm(self) -> float | None:
        return self.spindle

    @property
    def diameter(self) -> float:
        return self.cutter.diameter

    @property
    def radius(self) -> float:
        return self.cutter.radius

    @property
    def corner_radius(self) -> float:
        return self.cutter.corner_radius

    @property
    def type(self) -> str:
        """The cutter's registered kind (flat, ball, toroidal, tapered_ball...)."""
        return self.cutter.kind

    def label(self) -> str:
        """The name, else the cutter's short label (``toroidal D16 r3``, ``ball D12``)."""
        return self.name or self.cutter.short_label()


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

#: Choi's four cutters (D 6.35 mm: ball, toroidal r 1 and 1.27, flat), the zoning runs' tools
CHOI_TOOLS = [
    {"id": 1, "type": "ball", "diameter": 6.35},
    {"id": 2, "type": "toroidal", "diameter": 6.35, "corner_radius": 1.0},
    {"id": 3, "type": "toroidal", "diameter": 6.35, "corner_radius": 1.27},
    {"id": 4, "type": "flat", "diameter": 6.35},
]


class ToolDatabase:
    """Ordered tools; their cutters (:meth:`cutter`, ``cutters``) and array views ``R``
    (radius: the planner's step-over in mm from the gene's % of D) and ``ids`` for vectorized
    lookups by index (a corner radius: ``cutter(i).corner_radius``)."""

    def __init__(self, tools: list[Tool]):
        self.tools = list(tools)
        self.cutters = [t.cutter for t in self.tools]
        self.ids = np.array([t.id for t in self.tools], dtype=int)
        self.R = np.array([c.radius for c in self.cutters], dtype=float)

    def __len__(self) -> int:
        return len(self.tools)

    def feeds(self, feed_rate: float) -> np.ndarray:
        """(n,) the feed (mm/min) each tool's plans are programmed at, in their APT and NC
        files and in both machining times: the tool's library ``feed``, else ``feed_rate``."""
        return np.array([t.feed or float(feed_rate) for t in self.tools], dtype=float)

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
