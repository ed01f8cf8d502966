"""Rotary angles of a 5-axis machine from tool axes, and back (machine-kinematics config).

Two layouts, each with a tilting axis (about X or Y) and a rotary table about Z:

- ``table_table``: a trunnion tilts the table (angle a about X for an A axis, Y for a B axis)
  and carries the rotary table (angle c about Z) that holds the part; the spindle stays
  vertical. The tool axis seen from the part is t = Rz(-c) R_tilt(-a) z.
- ``head_table``: the head tilts the spindle by a; the rotary table turns the part by c:
  t = Rz(-c) R_tilt(+a) z.

Inverse (``angles``): cos a = t_z, so a = +-acos(t_z) (the two branches), and c turns the
tilted axis' azimuth onto t's. Along a path the branch and the turn (c + 360 k) are chosen
to stay closest to the previous point's angles within the limits; at the pole (t = z, where c
is free) c keeps its previous value and the tilt passes through 0 by changing sign, so the
table never flips by 180 degrees there.

Between two points the control interpolates the rotary angles linearly, so the tool axis
leaves the great circle between the two axes; ``deviation`` measures by how much at the
midpoint. A move is flagged ``unwind`` when the turn would leave the rotary limits (the table
must go round the other way) or when that deviation exceeds ``max_deviation`` (degrees; a
large turn at a large tilt): the post-processor then retracts, turns with the tool clear and
re-approaches. Other moves whose angles change by more than ``max_step`` degrees are split
by the post into equal steps (the same motion, written out).

Safety settings (used by the posts and checked by ``export.safety.check_program``):
``rotary_threshold`` (deg): a move turning a rotary by more than this happens only at the
clearance plane (the post retracts along the tool axis, rises to the plane, turns there and
comes down over the next point); ``pole_angle`` (deg): while |tilt| is below it the rotary
table holds its value and the tilt is the signed angle of the axis in the held tilt plane
(the axis then deviates from the wanted one by at most the azimuth error's projection, below
``pole_angle``; 0 disables the hold and keeps the exact axis with the least-travel branch);
``rapid_linear`` (mm/min) and ``rapid_rotary`` (deg/min) are the machine's rapid rates
(machining time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

POLE = 1e-12


class ReachError(ValueError):
    """A tool axis that no pair of rotary angles within the limits reaches."""


@dataclass(frozen=True)
class Rotary:
    """A rotary axis: address letter, rotation axis ('x', 'y' or 'z'), limits (deg)."""

    name: str
    about: str
    limits: tuple[float, float] = (-math.inf, math.inf)


@dataclass(frozen=True)
class Kinematics:
    layout: str          # "table_table" | "head_table"
    tilt: Rotary         # about x or y
    rotary: Rotary       # about z
    max_step: float = 10.0
    max_deviation: float = 5.0
    rotary_threshold: float = 20.0
    pole_angle: float = 0.5
    rapid_linear: float = 10000.0
    rapid_rotary: float = 5400.0

    def __post_init__(self):
        if self.layout not in ("table_table", "head_table"):
            raise ValueError(f"layout: expected table_table or head_table, got {self.layout!r}")
        if self.tilt.about not in ("x", "y") or self.rotary.about != "z":
            raise ValueError("the tilting axis turns about x or y and the rotary table about z")
        for ax in (self.tilt, self.rotary):
            if not ax.limits[0] < ax.limits[1]:
                raise ValueError(f"limits of {ax.name}: lower must be below upper, got {list(ax.limits)}")
        for key in ("max_step", "max_deviation", "rotary_threshold", "rapid_linear", "rapid_rotary"):
            if not getattr(self, key) > 0:
                raise ValueError(f"{key}: must be > 0, got {getattr(self, key)!r}")
        if not 0 <= self.pole_angle < 90:
            raise ValueError(f"pole_angle: must be in [0, 90), got {self.pole_angle!r}")

    @property
    def _sign(self) -> float:
        return -1.0 if self.layout == "table_table" else 1.0

    def _tilted(self, a_rad: np.ndarray) -> np.ndarray:
        """R_tilt(sign a) z, (n, 3)."""
        s, c = np.sin(self._sign * a_rad), np.cos(a_rad)
        zero = np.zeros_like(s)
        return np.column_stack([zero, -s, c] if self.tilt.about == "x" else [s, zero, c])

    def tool_axis(self, a_deg, c_deg) -> np.ndarray:
        """Forward kinematics: unit tool axes (n, 3) in the part frame for angles (deg)."""
        a, c = np.radians(np.atleast_1d(a_deg)), np.radians(np.atleast_1d(c_deg))
        w = self._tilted(a)
        cc, sc = np.cos(-c), np.sin(-c)
        return np.column_stack([w[:, 0] * cc - w[:, 1] * sc, w[:, 0] * sc + w[:, 1] * cc, w[:, 2]])

    def _candidates(self, t, prev_c):
        """The (a, c) pairs (deg) reaching axis t: both tilt branches (one at the pole)."""
        a = math.degrees(math.acos(max(-1.0, min(1.0, t[2]))))
        if math.hypot(t[0], t[1]) < POLE:
            return [(a, prev_c)] if a == 0 else [(a, prev_c), (-a, prev_c)]
        out = []
        for branch in (a, -a):
            w = self._tilted(np.radians([branch]))[0]
            c = math.degrees(math.atan2(w[1], w[0]) - math.atan2(t[1], t[0]))
            out.append((branch, c))
        return out

    def _wrap(self, c: float, prev_c: float) -> tuple[float, bool]:
        """c + 360 k closest to prev_c within the rotary limits; (value, had to leave the closest)."""
        lo, hi = self.rotary.limits
        near = c + 360.0 * round((prev_c - c) / 360.0)
        if lo - 1e-9 <= near <= hi + 1e-9:
            return near, False
        k = np.arange(-4, 5)
        options = near + 360.0 * k
        options = options[(options >= lo - 1e-9) & (options <= hi + 1e-9)]
        if len(options) == 0:
            return math.nan, True
        return float(options[np.argmin(np.abs(options - prev_c))]), True

    def angles(self, axes: np.ndarray, start_c: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Inverse kinematics along a path: angles (m, 2) = (a, c) in degrees and unwind (m,)
        (True where the move into the point needs a reposition). Raises ``ReachError`` naming
        the first point whose axis is out of reach."""
        axes = np.asarray(axes, float)
        axes = axes / np.linalg.norm(axes, axis=1, keepdims=True)
        out = np.empty((len(axes), 2))
        unwind = np.zeros(len(axes), bool)
        prev_a, prev_c = 0.0, float(start_c)
        lo, hi = self.tilt.limits
        for n, t in enumerate(axes):
            best = None
            for a, c in self._candidates(t, prev_c):
                if not lo - 1e-9 <= a <= hi + 1e-9:
                    continue
                c, forced = self._wrap(c, prev_c)
                if math.isnan(c):
                    continue
                step = max(abs(a - prev_a), abs(c - prev_c)) if n else 0.0
                if best is None or step < best[0]:
                    best = (step, a, c, forced)
            if best is None:
                raise ReachError(f"point {n}: tool axis ({t[0]:.6f}, {t[1]:.6f}, {t[2]:.6f}) is out of reach of "
                                 f"{self.tilt.name} in [{lo:g}, {hi:g}] and {self.rotary.name} in "
                                 f"[{self.rotary.limits[0]:g}, {self.rotary.limits[1]:g}] degrees")
            step, prev_a, prev_c, forced = best
            if n and abs(prev_a) < self.pole_angle and best[2] != out[n - 1, 1]:
                prev_c, held = out[n - 1, 1], self._held_tilt(t, out[n - 1, 1])
                if lo - 1e-9 <= held <= hi + 1e-9:
                    prev_a, forced = held, False
                else:
                    prev_c = best[2]
            out[n] = prev_a, prev_c
            unwind[n] = n > 0 and forced
        unwind[1:] |= self.deviation(axes[:-1], axes[1:], out[:-1], out[1:]) > self.max_deviation
        return out, unwind

    def _held_tilt(self, t, c_deg: float) -> float:
        """The tilt (deg) whose axis at rotary ``c_deg`` is closest to t: t turned back by
        Rz(c) and its signed angle from z in the tilt plane."""
        c = math.radians(c_deg)
        x, y = t[0] * math.cos(c) - t[1] * math.sin(c), t[0] * math.sin(c) + t[1] * math.cos(c)
        along = -y if self.tilt.about == "x" else x
        return self._sign * math.degrees(math.atan2(along, t[2]))

    def deviation(self, t0, t1, ang0, ang1) -> np.ndarray:
        """Angle (deg) at the midpoint between the axis the linearly interpolated rotaries give
        and the great-circle midpoint of the axes t0, t1 (each (n, 3))."""
        mid = 0.5 * (np.asarray(ang0) + np.asarray(ang1))
        machine = self.tool_axis(mid[:, 0], mid[:, 1])
        ideal = np.asarray(t0) + np.asarray(t1)
        norm = np.linalg.norm(ideal, axis=1, keepdims=True)
        ideal = np.where(norm > 1e-9, ideal / np.maximum(norm, 1e-300), machine)
        return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", machine, ideal), -1.0, 1.0)))
