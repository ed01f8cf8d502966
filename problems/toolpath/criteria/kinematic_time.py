"""Machining time as the machine runs it: a jerk-limited (S-curve) feed profile per move.

The path is a chain of straight moves (a G1 block per move). The control's path speed v
obeys |dv/dt| <= A (acceleration) and |d2v/dt2| <= J (jerk); every speed change follows the
symmetric S-curve (acceleration ramps up at J, holds at A if it gets there, ramps down at
J): a jerk-limited 7-segment S-curve, not a trapezoid. The control looks ahead: moves
between two "knots" (vertices whose corner limits the speed below the feed, feed changes,
chain ends) are one S-curve stretch; the acceleration is zero at the knots. The limits are applied to the path speed, so
no axis exceeds them (each axis' share is at most the path's).

A speed change dv (Herraz et al. evaluate time with these limits; the closed forms are the
standard jerk-limited profile):

    T(dv) = dv / A + A / J        if dv >= A^2 / J        (the acceleration reaches A)
          = 2 sqrt(dv / J)        otherwise
    D(v0, v1) = (v0 + v1) / 2 * T(|v1 - v0|)               (symmetric profile: mean speed)

Speed at a vertex: at most the feeds of both moves and the corner speed of the direction
change theta between them, from the junction-deviation rule (the control rounds the corner
by an arc that deviates ``corner_tolerance`` delta from the vertex, at centripetal
acceleration A):

    v_c^2 = A delta s / (1 - s),  s = sin(theta_turn / 2) with cos(theta_turn) = -u_in . u_out

so a straight continuation has no limit and a reversal stops (v_c = 0). The chain starts
and ends at rest. A forward and a backward pass bring every vertex speed down to what the
neighbouring moves can reach within their lengths (D <= L); each move then accelerates to
its feed (or to the highest peak it has room for), cruises and decelerates. Rapids run the
same model at the rapid rate, plunges at the plunge feed.

Closed forms the tests use: a straight line of length L >= F T(F) from rest to rest takes
L / F + T(F); every full stop on the way (a reversal) adds T(F); A, J -> infinity gives L / F.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from pydantic import BaseModel, ConfigDict, Field, field_validator

__all__ = ["Dynamics", "chain_time", "plan_times", "kinematic_time", "toolpath_time", "moves_time"]


class Dynamics(BaseModel):
    """The machine's limits: ``accel`` m/s^2, ``jerk`` m/s^3, ``feed`` mm/min (only for an NC
    move that names no feed: a plan runs at its programmed feed, the tool library's or
    ``feed_rate``), ``rapid`` mm/min, ``corner_tolerance`` mm (junction deviation), each > 0
    (``rapid`` may be infinite). Defaults: Herraz et al.'s jerk 40 m/s^3, acceleration
    6 m/s^2, feed 5 m/min. A run file's ``dynamics`` mapping is this model."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    accel: float = Field(6.0, description="m/s^2")
    jerk: float = Field(40.0, description="m/s^3")
    feed: float = Field(5000.0, description="mm/min, for an NC move that names no feed")
    rapid: float = Field(10000.0, description="mm/min")
    corner_tolerance: float = Field(0.01, description="mm (junction deviation)")

    @field_validator("*", mode="before")
    @classmethod
    def _positive(cls, v):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) or v == math.inf):
            raise ValueError(f"expected a number, got {v!r}")
        if not v > 0:
            raise ValueError(f"must be > 0, got {v!r}")
        return float(v)

    @property
    def a_mm(self) -> float:
        return self.accel * 1000.0

    @property
    def j_mm(self) -> float:
        return self.jerk * 1000.0


@njit(cache=True)
def _t(dv, a, j):
    """S-curve time of a speed change dv >= 0."""
    if dv <= 0.0:
        return 0.0
    if dv >= a * a / j:
        return dv / a + a / j
    return 2.0 * math.sqrt(dv / j)


@njit(cache=True)
def _d(v0, v1, a, j):
    """Distance of the S-curve from v0 to v1."""
    return 0.5 * (v0 + v1) * _t(abs(v1 - v0), a, j)


@njit(cache=True)
def _reach(v0, length, vmax, a, j):
    """The highest speed <= vmax reachable from v0 over ``length`` (speeding up)."""
    if _d(v0, vmax, a, j) <= length:
        return vmax
    lo, hi = v0, vmax
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _d(v0, mid, a, j) <= length:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def _move_time(v0, v1, length, f, a, j):
    """Time of one move: v0 -> peak (<= f) -> v1 over ``length``."""
    if length <= 0.0:
        return 0.0
    d0, d1 = _d(v0, f, a, j), _d(f, v1, a, j)
    if d0 + d1 <= length:
        return _t(f - v0, a, j) + _t(f - v1, a, j) + (length - d0 - d1) / f
    lo, hi = max(v0, v1), f
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _d(v0, mid, a, j) + _d(mid, v1, a, j) <= length:
            lo = mid
        else:
            hi = mid
    vp = lo
    used = _d(v0, vp, a, j) + _d(vp, v1, a, j)
    return _t(vp - v0, a, j) + _t(vp - v1, a, j) + max(length - used, 0.0) / max(vp, 1e-12)


@njit(cache=True)
def _chains(pts, feed, start, a, j, delta, out):
    """Time (s) of the stretch of moves ending at each knot into out[knot] (0 elsewhere); a
    chain starts where ``start`` is True; feed[i] mm/s of move i-1 -> i."""
    n = len(pts)
    length = np.zeros(n)
    unit = np.zeros((n, 3))
    for i in range(1, n):  # scalars only: an array temporary per move is a heap allocation
        if start[i]:
            continue
        dx, dy, dz = pts[i, 0] - pts[i - 1, 0], pts[i, 1] - pts[i - 1, 1], pts[i, 2] - pts[i - 1, 2]
        ln = math.sqrt(dx * dx + dy * dy + dz * dz)
        length[i] = ln
        if ln > 0.0:
            unit[i, 0], unit[i, 1], unit[i, 2] = dx / ln, dy / ln, dz / ln
        else:
            unit[i, 0], unit[i, 1], unit[i, 2] = unit[i - 1, 0], unit[i - 1, 1], unit[i - 1, 2]
    vmax = np.zeros(n)
    for i in range(n):
        end = i == n - 1 or start[i + 1]
        if start[i] or end:
            vmax[i] = 0.0
            continue
        v = min(feed[i], feed[i + 1])
        c = -(unit[i, 0] * unit[i + 1, 0] + unit[i, 1] * unit[i + 1, 1] + unit[i, 2] * unit[i + 1, 2])
        s = math.sqrt(max(0.5 * (1.0 - c), 0.0))  # sin(theta / 2): 1 straight on, 0 a reversal
        if s < 1.0 - 1e-12:
            v = min(v, math.sqrt(a * delta * s / (1.0 - s)))
        vmax[i] = v
    # a vertex that limits the speed (or changes the feed, or starts/ends a chain) is a knot;
    # between knots the moves are one S-curve (the look-ahead carries the acceleration on)
    knot = np.zeros(n, np.bool_)
    for i in range(n):
        if start[i] or i == n - 1 or start[i + 1] or feed[i] != feed[i + 1] or vmax[i] < feed[i] * (1 - 1e-12):
            knot[i] = True
    ks = np.flatnonzero(knot)
    m = len(ks)
    seg_len = np.zeros(m)
    seg_feed = np.zeros(m)
    for q in range(1, m):
        acc = 0.0
        for i in range(ks[q - 1] + 1, ks[q] + 1):
            acc += length[i]
        seg_len[q] = acc
        seg_feed[q] = feed[ks[q]]
    vel = np.zeros(m)
    for q in range(m):
        vel[q] = vmax[ks[q]]
    for q in range(1, m):  # forward: what the stretch into knot q can reach
        if not _starts(start, ks[q - 1], ks[q]):
            vel[q] = min(vel[q], _reach(vel[q - 1], seg_len[q], seg_feed[q], a, j))
    for q in range(m - 2, -1, -1):  # backward: what the stretch out of knot q can brake from
        if not _starts(start, ks[q], ks[q + 1]):
            vel[q] = min(vel[q], _reach(vel[q + 1], seg_len[q + 1], seg_feed[q + 1], a, j))
    for q in range(1, m):
        if not _starts(start, ks[q - 1], ks[q]):
            out[ks[q]] = _move_time(vel[q - 1], vel[q], seg_len[q], seg_feed[q], a, j)


@njit(cache=True)
def _starts(start, k0, k1):
    """True if a chain starts after k0 up to k1 (the knots are in different chains)."""
    for i in range(k0 + 1, k1 + 1):
        if start[i]:
            return True
    return False


def chain_time(points, feed_mm_min, dyn: Dynamics, start=None) -> np.ndarray:
    """Time in seconds (m,) of the chain(s) of ``points`` (m, 3), each stretch between speed
    knots booked at its last point (the sum over a chain is its time); ``feed_mm_min`` a
    scalar or (m,) feed of the move into each point; ``start`` (m,) True where a chain
    starts at rest (default: only the first point); every chain ends at rest."""
    pts = np.ascontiguousarray(points, float).reshape(-1, 3)
    m = len(pts)
    feed = np.broadcast_to(np.asarray(feed_mm_min, float) / 60.0, (m,)).copy()
    st = np.zeros(m, bool) if start is None else np.asarray(start, bool).copy()
    if m:
        st[0] = True
    out = np.zeros(m)
    if m:
        _chains(pts, feed, st, dyn.a_mm, dyn.j_mm, dyn.corner_tolerance, out)
    return out


def plan_times(batch, dyn: Dynamics, feed_mm_min) -> np.ndarray:
    """Kinematic machining time (min) per plan (n,) of a ``PlanBatch``: each plan's sections
    in machining order joined by their link moves at the feed into one chain per zone
    (the tool does not stop between sections of a zone unless a corner makes it); a zone
    change is a stop, a straight rapid at ``dyn.rapid`` and a stop. ``feed_mm_min`` per plan
    (n,) (the plan's tool feed)."""
    n = batch.n
    if n == 0:
        return np.zeros(0)
    p = np.asarray(batch.p, float)
    pt_sec = np.asarray(batch.pt_sec)
    sec_ind = np.asarray(batch.sec_ind)
    sec_zone = np.asarray(batch.sec_zone)
    pt_ind = sec_ind[pt_sec]
    # a chain starts at a plan's first point or where the zone changes
    zone_pt = sec_zone[pt_sec]
    new_chain = np.r_[True, (pt_ind[1:] != pt_ind[:-1]) | (zone_pt[1:] != zone_pt[:-1])]
    feed = np.asarray(feed_mm_min, float).reshape(-1)[pt_ind] if np.ndim(feed_mm_min) else \
        np.full(len(p), float(feed_mm_min))
    t = chain_time(p, feed, dyn, start=new_chain)
    total = np.bincount(pt_ind, t, n)
    # rapids between zones: from rest to rest at the rapid rate
    hop = np.flatnonzero(new_chain[1:] & (pt_ind[1:] == pt_ind[:-1])) + 1
    if len(hop):
        pair = np.empty((2 * len(hop), 3))
        pair[0::2], pair[1::2] = p[hop - 1], p[hop]
        st = np.zeros(2 * len(hop), bool)
        st[0::2] = True
        tr = chain_time(pair, dyn.rapid, dyn, start=st)[1::2]
        total += np.bincount(pt_ind[hop], tr, n)
    return total / 60.0


def kinematic_time(batch, feed, dynamics=None) -> np.ndarray:
    """``machining_time`` (min) per plan: :func:`plan_times` at each plan's programmed feed
    ``feed`` (n,) mm/min, the one its APT and NC programs carry (``ToolDatabase.feeds``), so
    it is never below the length over that feed."""
    return plan_times(batch, dynamics or Dynamics(), feed)


def toolpath_time(tp, dyn: Dynamics | None = None) -> float:
    """Kinematic time (min) of an NC operation (``export.toolpath.Toolpath``): its feed moves
    as chains under the limits (plunges at the plunge feed, a feed change is a speed knot),
    every rapid from rest to rest at ``dyn.rapid``."""
    feed = np.where(np.asarray(tp.plunge, bool), tp.plunge_feed, tp.feed)
    return moves_time(tp.tip, tp.rapid, feed, dyn)


def moves_time(tip, rapid, feed, dyn: Dynamics | None = None, angles=None,
               rapid_rotary: float | None = None) -> float:
    """Kinematic time (min) of NC moves (the points ``tip`` (m, 3), ``rapid`` (m,) True for a
    rapid into the point, ``feed`` (m,) mm/min of a feed move): feed moves as chains under the
    limits (a feed change is a speed knot), every rapid from rest to rest at ``dyn.rapid``;
    with ``angles`` (m, 2) deg and ``rapid_rotary`` deg/min, a rapid that turns a rotary takes
    the longer of its linear and its rotary time (the rotary at constant rate: the program as
    read back, repositions included)."""
    dyn = dyn or Dynamics()
    tip = np.asarray(tip, float)
    rapid = np.asarray(rapid, bool)
    feed = np.where(rapid, dyn.rapid, np.nan_to_num(np.asarray(feed, float), nan=dyn.feed))
    t = chain_time(tip, feed, dyn, start=rapid).sum()
    hop = np.flatnonzero(rapid[1:]) + 1
    if len(hop):
        pair = np.empty((2 * len(hop), 3))
        pair[0::2], pair[1::2] = tip[hop - 1], tip[hop]
        st = np.zeros(2 * len(hop), bool)
        st[0::2] = True
        linear = chain_time(pair, dyn.rapid, dyn, start=st)[1::2]
        if angles is not None and rapid_rotary:
            turn = np.nan_to_num(np.abs(np.diff(np.asarray(angles, float), axis=0))).max(axis=1)[hop - 1]
            linear = np.maximum(linear, 60.0 * turn / rapid_rotary)
        t += linear.sum()
    return float(t) / 60.0
