"""One NC operation's toolpath: the moves every writer (APT, the G-code posts, DXF) reads.

Points are in machining order; the flags say how the tool moves INTO each point:
``rapid`` (positioning, no cut), ``plunge`` (cutting at the plunge feed), else cutting at the
operation's feed. ``section`` is the pass or layer a point belongs to (-1 for approach and
retract moves); ``section_names`` may name a section (e.g. ``ZONE 2 PASS 7``) for the comment
that opens it. Without a ``plunge_feed``, the plunges are cut at the tool's ``plunge_feed`` or,
if it has none, at half the feed (the APT and the NC programs of a plan share it).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import PurePath

import numpy as np

from ..tools import Tool

__all__ = ["Tool", "Toolpath", "surface_comment"]


def surface_comment(surface, spec=None) -> str:
    """The header comment naming the part's surface, for the APT file and the NC programs:
    its type and file and, for a fitted one (``type: mesh``, a height field fitted to the
    triangles), the fit's largest measured deviation from the mesh, e.g. ``surface: mesh
    wavy_mesh.stl, fit max deviation 0.002623 mm`` (one line of the header; a long
    file name wraps as any comment). ``spec``: the surface as the
    run file gives it (a type name, a mapping or the validated settings) for the type and
    file; else the surface's ``facts()`` say them (a mesh), else its class."""
    facts = surface.facts() if callable(getattr(surface, "facts", None)) else {}
    if isinstance(spec, str):
        spec = {"type": spec}
    get = spec.get if isinstance(spec, dict) else lambda k, d=None: getattr(spec, k, d)
    kind = get("type") or facts.get("type") or type(surface).__name__
    file = get("file") or facts.get("file")
    text = f"surface: {kind}" + (f" {PurePath(str(file)).name}" if file else "")
    fit = facts.get("fit")
    if isinstance(fit, dict) and "max_deviation_mm" in fit:
        text += f", fit max deviation {float(fit['max_deviation_mm']):.4g} mm"
    return text


@dataclass
class Toolpath:
    """tip (m, 3) tool tip; axis (m, 3) unit tool axis; rapid/plunge (m,) bool; section (m,)."""

    name: str
    tool: Tool
    tip: np.ndarray
    axis: np.ndarray
    rapid: np.ndarray
    plunge: np.ndarray
    section: np.ndarray
    feed: float
    plunge_feed: float
    section_label: str = "PASS"
    comments: list[str] = field(default_factory=list)
    section_names: dict[int, str] = field(default_factory=dict)

    def __post_init__(self):
        self.tip = np.asarray(self.tip, float).reshape(-1, 3)
        self.axis = np.asarray(self.axis, float).reshape(-1, 3)
        m = len(self.tip)
        self.rapid = np.asarray(self.rapid, bool).reshape(m)
        self.plunge = np.asarray(self.plunge, bool).reshape(m)
        self.section = np.asarray(self.section, int).reshape(m)
        if self.axis.shape != self.tip.shape or m == 0:
            raise ValueError(f"{self.name}: tip and axis must be (m, 3) with m > 0")

    def section_name(self, k: int) -> str:
        """The comment text that opens section ``k``: its name, else ``<section_label> k``."""
        return self.section_names.get(int(k), f"{self.section_label} {int(k)}")

    @property
    def multi_axis(self) -> bool:
        """True unless every axis is +Z (a 3-axis program)."""
        return not np.allclose(self.axis, [0.0, 0.0, 1.0], atol=1e-12)

    def segment_lengths(self) -> np.ndarray:
        """(m,) length of the move into each point (0 for the first)."""
        return np.r_[0.0, np.linalg.norm(np.diff(self.tip, axis=0), axis=1)]

    def lengths(self) -> dict[str, float]:
        """Cutting (feed), plunge and rapid lengths, mm."""
        seg = self.segment_lengths()
        cut = ~self.rapid & ~self.plunge
        return {"cutting": float(seg[cut].sum()), "plunge": float(seg[self.plunge].sum()),
                "rapid": float(seg[self.rapid].sum())}

    def time_minutes(self, rapid_rate: float) -> float:
        """Machining time at the programmed feeds and the machine's rapid rate (mm/min)."""
        ln = self.lengths()
        return ln["cutting"] / self.feed + ln["plunge"] / self.plunge_feed + ln["rapid"] / rapid_rate

    @classmethod
    def from_passes(cls, name: str, tool: Tool, tip, axis, pass_index, *, feed: float,
                    plunge_feed: float | None = None, clearance: float = 10.0, comments=None) -> "Toolpath":
        """A finishing toolpath from passes in machining order: a rapid to ``clearance`` above
        the first point along its axis, the plunge to it, the passes linked by cutting moves,
        and a rapid retract of ``clearance`` along the last axis."""
        tip, axis, pass_index = np.asarray(tip, float), np.asarray(axis, float), np.asarray(pass_index, int)
        if tip.ndim != 2 or tip.shape[1] != 3 or axis.shape != tip.shape or len(pass_index) != len(tip):
            raise ValueError("tip and axis must be (m, 3) and pass_index (m,)")
        if len(tip) == 0:
            raise ValueError("an empty toolpath has no NC program")
        m = len(tip)
        pts = np.vstack([tip[:1] + clearance * axis[:1], tip, tip[-1:] + clearance * axis[-1:]])
        ax = np.vstack([axis[:1], axis, axis[-1:]])
        rapid = np.r_[True, np.zeros(m, bool), True]
        plunge = np.r_[False, True, np.zeros(m, bool)]
        return cls(name, tool, pts, ax, rapid, plunge, np.r_[-1, pass_index, -1], feed,
                   _plunge_feed(tool, feed, plunge_feed), comments=list(comments or []))

    @classmethod
    def from_sections(cls, name: str, tool: Tool, tip, axis, section, *, feed: float,
                      plunge_feed: float | None = None, clearance: float = 10.0, gap: float = 1.0,
                      comments=None, section_names=None) -> "Toolpath":
        """A finishing toolpath cut in separate sections (e.g. the stretches of a zoned plan):
        every run of equal ``section`` (m,) is entered by a rapid to the safe height (the
        highest point plus ``clearance``) above its first point, a rapid down to ``gap`` above
        it along its axis and a plunge, is cut point to point, and is left by a rapid retract
        straight up to the safe height. Section k keeps its number (``section_names`` may
        name it for the comments)."""
        tip, axis, section = np.asarray(tip, float), np.asarray(axis, float), np.asarray(section, int)
        if tip.ndim != 2 or tip.shape[1] != 3 or axis.shape != tip.shape or len(section) != len(tip):
            raise ValueError("tip and axis must be (m, 3) and section (m,)")
        if len(tip) == 0:
            raise ValueError("an empty toolpath has no NC program")
        safe = tip[:, 2].max() + clearance
        starts = np.flatnonzero(np.r_[True, section[1:] != section[:-1]])
        pieces = []  # (points, axes, rapid, plunge, section) per block of moves
        for a, b in zip(starts, np.r_[starts[1:], len(tip)]):
            first, last = tip[a], tip[b - 1]
            above = [[first[0], first[1], safe], first + gap * axis[a]]
            pieces.append((above, axis[[a, a]], [True, True], [False, False], [-1, -1]))
            plunge = np.zeros(b - a, bool)
            plunge[0] = True
            pieces.append((tip[a:b], axis[a:b], np.zeros(b - a, bool), plunge, section[a:b]))
            pieces.append(([[last[0], last[1], safe]], axis[b - 1:b], [True], [False], [-1]))
        pts, ax, rapid, plunge, sec = (np.concatenate([np.asarray(p[i]) for p in pieces])
                                       for i in range(5))
        return cls(name, tool, pts, ax, rapid, plunge, sec, feed, _plunge_feed(tool, feed, plunge_feed),
                   comments=list(comments or []), section_names=dict(section_names or {}))


def _plunge_feed(tool: Tool, feed: float, plunge_feed: float | None) -> float:
    """The plunge feed given, else the tool's ``plunge_feed``, else half ``feed`` (mm/min)."""
    if plunge_feed is not None:
        return plunge_feed
    return tool.plunge_feed if getattr(tool, "plunge_feed", None) is not None else 0.5 * feed


def drop_collinear(points: np.ndarray, tol: float) -> np.ndarray:
    """Mask (n,) of the points of a polyline to keep so that every dropped point lies within
    ``tol`` of the segment between the kept points around it (ends kept): the line blocks of
    ``arcs.fit_blocks``. The distance is to the segment, not to its line, so a reversal along
    a line (there and back) keeps its turning point."""
    from .arcs import fit_blocks

    points = np.asarray(points, float)
    keep = np.zeros(len(points), bool)
    if len(points) < 3:
        keep[:] = True
        return keep
    keep[0] = True
    keep[fit_blocks(points, tol, arcs=False).end] = True
    return keep
