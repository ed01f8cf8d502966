"""Display decimation of polylines: Ramer-Douglas-Peucker within a stated tolerance.

A point is dropped only if it lies within ``tol`` mm of the chord kept in its place, so the
drawn polyline never strays more than ``tol`` from the programmed one (the guarantee of RDP,
checked in ``tests/report/test_decimate.py`` against the point-to-polyline distance).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["rdp_keep", "decimate_runs", "fit_budget"]


@numba.njit(cache=True)
def _rdp(p, lo, hi, tol2, keep, stack):
    top = 0
    stack[0, 0], stack[0, 1] = lo, hi
    top = 1
    while top > 0:
        top -= 1
        a, b = stack[top, 0], stack[top, 1]
        keep[a] = True
        keep[b] = True
        if b - a < 2:
            continue
        d = p[b] - p[a]
        dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        worst, at = -1.0, -1
        for i in range(a + 1, b):
            w = p[i] - p[a]
            if dd > 0.0:
                t = (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / dd
                t = min(1.0, max(0.0, t))
            else:
                t = 0.0
            e0, e1, e2 = w[0] - t * d[0], w[1] - t * d[1], w[2] - t * d[2]
            dist = e0 * e0 + e1 * e1 + e2 * e2
            if dist > worst:
                worst, at = dist, i
        if worst > tol2:
            stack[top, 0], stack[top, 1] = a, at
            stack[top + 1, 0], stack[top + 1, 1] = at, b
            top += 2


@numba.njit(cache=True)
def _runs(p, starts, ends, tol2, keep):
    stack = np.empty((max(2 * p.shape[0], 2), 2), np.int64)
    for k in range(starts.shape[0]):
        if ends[k] > starts[k]:
            _rdp(p, starts[k], ends[k], tol2, keep, stack)
        else:
            keep[starts[k]] = True


def rdp_keep(points: np.ndarray, tol: float) -> np.ndarray:
    """Boolean mask of the points of ONE polyline kept by RDP at ``tol`` (ends always kept)."""
    return decimate_runs(points, np.zeros(len(points), np.int64), tol)


def decimate_runs(points: np.ndarray, run: np.ndarray, tol: float) -> np.ndarray:
    """Mask of kept points of several polylines: consecutive points with equal ``run`` form one."""
    p = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3)
    keep = np.zeros(len(p), np.bool_)
    if len(p) == 0:
        return keep
    cut = np.flatnonzero(np.diff(run) != 0) + 1
    starts = np.r_[0, cut].astype(np.int64)
    ends = np.r_[cut - 1, len(p) - 1].astype(np.int64)
    _runs(p, starts, ends, float(tol) ** 2, keep)
    return keep


def fit_budget(points: np.ndarray, run: np.ndarray, budget: int, tol: float = 0.005
               ) -> tuple[np.ndarray, float]:
    """(mask, tolerance): the smallest tolerance ``tol * 2**k`` (k >= 0) whose RDP keeps at
    most ``budget`` points (or the last tried, 2**20 * tol)."""
    for _ in range(21):
        keep = decimate_runs(points, run, tol)
        if keep.sum() <= budget:
            break
        tol *= 2.0
    return keep, tol
