"""Zig-zag parallel-plane strategy over a whole footprint: the CC patterns of a batch.

Strategy (Fountas et al., "Experimental validation": multi-axis zig-zag sweeping, feed along
X, cut tolerance 0.01 mm):

- Passes are the sections of the surface by vertical planes parallel to the feed direction
  (``planes.PassGeometry``).
- **Step-over is measured in XY between the planes**, as CAM systems do: d_k = d_min + k
  delta with delta = step-over % x D, the last pass clamped on the far edge (d_max), so the
  last spacing may be shorter. On a slope the CC points of adjacent passes are further apart
  on the surface (delta / (b.c), with b the cross-feed tangent); the scallop uses that
  surface distance.
- CC points along each pass: the maximum step, then the chord tolerance (``points.py``).
- Pass 0 travels along +f, pass 1 along -f, and so on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .planes import PassGeometry
from .points import ranges, sample_sections

__all__ = ["PassGeometry", "PatternBatch", "cc_pattern_batch", "plane_offsets"]


@dataclass
class PatternBatch:
    """CC patterns of a batch of parameter sets, flattened.

    Passes (P of them): ``pass_ind`` individual, ``pass_k`` index within its toolpath,
    ``pass_d`` plane position, ``pass_start``/``pass_count`` its CC points (sorted along +f,
    i.e. tau ascending; odd passes are machined in reverse order), ``pass_spacing`` the XY
    distance to the next pass (to the previous for the last pass; 0 for a single pass).
    Points (N): ``pt_pass``, ``tau``, ``u``, ``v``, ``p`` (N, 3), ``chord`` the larger chord
    error of the two segments at the point. Segments (N - P): ``seg_pass``, ``seg_err``,
    ``seg_len``, ``seg_start`` (index of the first point).
    """

    n: int
    pass_ind: np.ndarray
    pass_k: np.ndarray
    pass_d: np.ndarray
    pass_start: np.ndarray
    pass_count: np.ndarray
    pass_spacing: np.ndarray
    pt_pass: np.ndarray
    tau: np.ndarray
    u: np.ndarray
    v: np.ndarray
    p: np.ndarray
    chord: np.ndarray
    seg_pass: np.ndarray
    seg_err: np.ndarray
    seg_len: np.ndarray
    seg_start: np.ndarray


def plane_offsets(geom: PassGeometry, delta):
    """Pass planes of n plans at XY step-over delta (n,) mm across the whole footprint:
    (pass_ind, pass_k, pass_d, pass_spacing, n_int) (see the module docstring)."""
    delta = np.asarray(delta, float)
    n_int = np.maximum(np.ceil(geom.width / delta - 1e-9).astype(int), 1)
    pass_ind, pass_k = ranges(n_int + 1)
    pass_d = geom.d_min + np.minimum(pass_k * delta[pass_ind], geom.width)
    last = pass_k == n_int[pass_ind]
    nxt = np.minimum(np.arange(len(pass_d)) + 1, len(pass_d) - 1)
    prv = np.maximum(np.arange(len(pass_d)) - 1, 0)
    pass_spacing = np.where(last, pass_d - pass_d[prv], pass_d[nxt] - pass_d)
    return pass_ind, pass_k, pass_d, pass_spacing, n_int


def cc_pattern_batch(geom: PassGeometry, delta, step, tol: float,
                     max_rounds: int = 6) -> PatternBatch:
    """CC patterns for n parameter sets: delta (n,) XY step-over (mm), step (n,) maximum
    discretization step (mm), tol the cut tolerance (mm). See the module docstring."""
    step = np.asarray(step, float)
    pass_ind, pass_k, pass_d, pass_spacing, _ = plane_offsets(geom, delta)
    zero = np.zeros(len(pass_d))
    sp = sample_sections(geom, pass_d, zero, zero + 1.0, step[pass_ind], tol, max_rounds)
    return PatternBatch(
        n=len(np.asarray(delta)), pass_ind=pass_ind, pass_k=pass_k, pass_d=pass_d,
        pass_start=sp.sec_start, pass_count=sp.sec_count, pass_spacing=pass_spacing,
        pt_pass=sp.pt_sec, tau=sp.tau, u=sp.u, v=sp.v, p=sp.p, chord=sp.chord,
        seg_pass=sp.seg_sec, seg_err=sp.seg_err, seg_len=sp.seg_len, seg_start=sp.seg_start)
