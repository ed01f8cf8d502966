"""A toolpath as the machine runs it: cutter-location (CL) points, tool axes and moves.

This is what every planner produces and what every consumer reads (the APT writer, the
post-processors, the cut simulation): the machine's view, with no model behind it.

- ``tip`` (m, 3): the tool tip, the centre of the cutter's end face on its axis (the APT
  ``GOTO`` point), in machining order.
- ``axis`` (m, 3): the unit tool axis, pointing from the tip up the shank.
- ``section`` (m,): consecutive points of one section are joined by feed moves (the machine
  interpolates linearly in position and in axis: tool-centre-point control); where the
  section changes, the tool retracts and re-enters (a rapid move, which does not cut).
- ``pass_index`` (m,): the pass each point belongs to (for comments and figures).
- ``zone`` (m,): the zone of a zoned plan (0 when the plan has one zone).
- ``cutter``: the :class:`~.cutters.Cutter` (its shape and dimensions).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .cutters import Cutter

__all__ = ["CLPath"]


@dataclass(frozen=True)
class CLPath:
    """Cutter-location points in machining order; see the module docstring."""

    tip: np.ndarray
    axis: np.ndarray
    cutter: Cutter
    section: np.ndarray | None = None
    pass_index: np.ndarray | None = None
    zone: np.ndarray | None = None
    feed_rate: float = 1000.0
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        tip = np.ascontiguousarray(np.asarray(self.tip, float).reshape(-1, 3))
        axis = np.asarray(self.axis, float)
        axis = np.broadcast_to(axis, tip.shape) if axis.shape == (3,) else axis.reshape(-1, 3)
        if axis.shape != tip.shape:
            raise ValueError(f"toolpath: {len(tip)} tips but {len(axis)} axes")
        norm = np.linalg.norm(axis, axis=1, keepdims=True)
        if len(tip) and not (np.isfinite(tip).all() and np.isfinite(axis).all() and (norm > 0).all()):
            raise ValueError("toolpath: CL points and axes must be finite, axes non-zero")
        m = len(tip)
        zeros = np.zeros(m, np.int64)
        object.__setattr__(self, "tip", tip)
        object.__setattr__(self, "axis", np.ascontiguousarray(axis / np.where(norm > 0, norm, 1.0)))
        for name in ("section", "pass_index", "zone"):
            val = getattr(self, name)
            val = zeros if val is None else np.asarray(val, np.int64).reshape(-1)
            if len(val) != m:
                raise ValueError(f"toolpath: {name} has {len(val)} entries for {m} CL points")
            object.__setattr__(self, name, val)
        if not isinstance(self.cutter, Cutter):
            raise ValueError(f"toolpath: the cutter must be a Cutter, got {self.cutter!r}")

    def __len__(self) -> int:
        return len(self.tip)

    @property
    def radius(self) -> float:
        """The cutter's radius R (mm): its reach from the axis."""
        return self.cutter.radius

    @property
    def feed_moves(self) -> np.ndarray:
        """(m - 1,) bool: move i (point i -> i + 1) is a feed move inside one section."""
        return self.section[1:] == self.section[:-1]

    @classmethod
    def from_apt(cls, apt) -> "CLPath":
        """The path of an APT CL file read by ``export.apt_read.read_apt``: a RAPID move
        starts a new section (it does not cut); a file whose points are the tool centre
        (``$$ TOOLPOINT CENTRE``) is moved down the axis to the tip (``Cutter.centre_to_tip``)."""
        tip = np.asarray(apt.tip, float)
        axis = np.asarray(apt.axis, float)
        if apt.cutter is None:
            raise ValueError("toolpath: the CL file has no CUTTER/ statement")
        if apt.tip_is_centre:
            tip = apt.cutter.centre_to_tip(tip, axis)
        section = np.cumsum(np.asarray(apt.rapid, bool))
        feed = np.asarray(apt.feed, float)
        rate = float(np.nanmax(feed)) if np.isfinite(feed).any() else 1000.0
        return cls(tip, axis, apt.cutter, section=section,
                   pass_index=np.asarray(apt.section), feed_rate=rate)

    def feed_length(self) -> float:
        """Length (mm) of the feed moves, tip travel: what the machine cuts along."""
        seg = np.linalg.norm(np.diff(self.tip, axis=0), axis=1)
        return float(seg[self.feed_moves].sum())
