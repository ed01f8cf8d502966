"""Where a surface exists in its parameter square: the trimmed, possibly non-convex domain.

A face of a CAD file is trimmed: only the part of its parameter rectangle inside its outer
loop and outside its holes is material. A :class:`Footprint` holds those boundary loops in
(u, v) (the outer loop first, then the holes) and answers ``contains(u, v)`` by the even-odd
rule over all loops (a point is material when an odd number of loops encloses it), so a hole
is a loop inside the outer one. The default footprint is the whole unit square.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Footprint", "UNIT_SQUARE"]


class Footprint:
    """Boundary loops in (u, v) (each (k, 2), closed implicitly) and the point-in-domain mask."""

    def __init__(self, loops, whole: bool = False):
        self.loops = [np.asarray(loop, dtype=float) for loop in loops]
        for i, loop in enumerate(self.loops):
            if loop.ndim != 2 or loop.shape[1] != 2 or len(loop) < 3:
                raise ValueError(f"footprint loop {i}: expected (k >= 3, 2) points, got {loop.shape}")
        self.whole = whole  # the entire unit square: contains() is a bounds test

    @property
    def outer(self) -> np.ndarray:
        """The outer loop (k, 2)."""
        return self.loops[0]

    @property
    def holes(self) -> list[np.ndarray]:
        """The hole loops, each (k, 2)."""
        return self.loops[1:]

    def contains(self, u, v) -> np.ndarray:
        """Boolean mask (n,): is (u, v) inside the trimmed domain (boundary points included)."""
        u = np.asarray(u, float).ravel()
        v = np.asarray(v, float).ravel()
        inside = (u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)
        if self.whole:
            return inside
        from matplotlib.path import Path

        pts = np.column_stack([u, v])
        odd = np.zeros(len(u), bool)
        for loop in self.loops:
            odd ^= Path(loop).contains_points(pts, radius=1e-12)
        return inside & odd

    def area(self) -> float:
        """Area in (u, v) of the domain (outer loop minus holes; shoelace formula)."""
        def shoelace(p):
            x, y = p[:, 0], p[:, 1]
            return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
        return shoelace(self.outer) - sum(shoelace(h) for h in self.holes)


UNIT_SQUARE = Footprint([[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]], whole=True)
