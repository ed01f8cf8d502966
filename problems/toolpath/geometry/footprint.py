"""Where a surface exists in its parameter square: the trimmed, possibly non-convex domain.

A face of a CAD file is trimmed: only the part of its parameter rectangle inside its outer
loop and outside its holes is material. A :class:`Footprint` holds those boundary loops in
(u, v) (the outer loop first, then the holes) and answers ``contains(u, v)`` by the even-odd
rule over all loops (a point is material when an odd number of loops encloses it), so a hole
is a loop inside the outer one (``crossings.py``). The default footprint is the whole unit
square. :meth:`Footprint.xy_loops` maps the loops onto the part's plan view.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Footprint", "UNIT_SQUARE", "footprint_of"]


class Footprint:
    """Boundary loops in (u, v) (each (k, 2), closed implicitly) and the point-in-domain mask."""

    def __init__(self, loops, whole: bool = False, sampled: bool = False):
        self.loops = [np.asarray(loop, dtype=float) for loop in loops]
        for i, loop in enumerate(self.loops):
            if loop.ndim != 2 or loop.shape[1] != 2 or len(loop) < 3:
                raise ValueError(f"footprint loop {i}: expected (k >= 3, 2) points, got {loop.shape}")
        self.whole = whole  # the entire unit square: contains() is a bounds test
        #: the loops were sampled along the curves on the part itself (a CAD face's trimming
        #: curves, within their deflection): straight between samples in XY too, never densified
        self.sampled = sampled

    @property
    def outer(self) -> np.ndarray:
        """The outer loop (k, 2)."""
        return self.loops[0]

    @property
    def holes(self) -> list[np.ndarray]:
        """The hole loops, each (k, 2)."""
        return self.loops[1:]

    def contains(self, u, v) -> np.ndarray:
        """Boolean mask (n,): is (u, v) inside the trimmed domain (the whole square: its
        boundary included; a point on a trimming loop may fall on either side)."""
        u = np.asarray(u, float).ravel()
        v = np.asarray(v, float).ravel()
        inside = (u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)
        if self.whole:
            return inside
        from .crossings import inside as even_odd

        return inside & even_odd(self.loops, u, v)

    def dense(self, step: float) -> list[np.ndarray]:
        """The loops with points at most ``step`` apart in (u, v), each (k, 2) (as they are
        when ``sampled``)."""
        if self.sampled:
            return list(self.loops)
        out = []
        for loop in self.loops:
            nxt = np.roll(loop, -1, axis=0)
            k = np.maximum(np.ceil(np.linalg.norm(nxt - loop, axis=1) / step).astype(int), 1)
            owner = np.repeat(np.arange(len(loop)), k)
            f = np.arange(len(owner)) - np.repeat(np.cumsum(k) - k, k)
            out.append(loop[owner] + (f / k[owner])[:, None] * (nxt[owner] - loop[owner]))
        return out

    def xy_loops(self, surface, step: float = 1.0 / 1024) -> list[np.ndarray]:
        """The loops in the part's plan view (k, 2): densified (:meth:`dense`; a straight
        (u, v) edge is curved in XY) and mapped through ``surface``."""
        return [surface.jet(uv[:, 0], uv[:, 1], order=0).p[:, :2] for uv in self.dense(step)]

    def area(self) -> float:
        """Area in (u, v) of the domain (outer loop minus holes; shoelace formula)."""
        def shoelace(p):
            x, y = p[:, 0], p[:, 1]
            return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
        return shoelace(self.outer) - sum(shoelace(h) for h in self.holes)


UNIT_SQUARE = Footprint([[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]], whole=True)


def footprint_of(surface) -> Footprint:
    """The surface's footprint, the unit square for a surface-like object without one."""
    return getattr(surface, "footprint", None) or UNIT_SQUARE
