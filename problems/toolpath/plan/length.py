"""Path length and machining time of zig-zag toolpaths, batched.

The path is the polyline through the CC points in machining order (pass 0 along +f, pass 1
back along -f, ...): the cutting length is the sum of its chords, the links are the straight
moves from the end of each pass to the start of the next (on the footprint's edge in
zig-zag), and the time is (cutting + links) / feed rate, all at the feed rate (no rapid
moves, no acceleration limits). Lengths are measured at the CC points; with lead and tilt
the tool tip travels a slightly different length.
"""

from __future__ import annotations

import numpy as np

from .pattern import PatternBatch

__all__ = ["cutting_length", "link_length", "machining_time", "travel_order"]


def cutting_length(pb: PatternBatch) -> np.ndarray:
    """Sum of the chord lengths per individual: (n,) mm."""
    return np.bincount(pb.pass_ind[pb.seg_pass], weights=pb.seg_len, minlength=pb.n)


def link_length(pb: PatternBatch) -> np.ndarray:
    """Length of the moves between consecutive passes per individual: (n,) mm.

    Pass k (even) ends at its +f end and pass k+1 starts there; pass k odd ends at its -f end.
    """
    nxt = np.arange(len(pb.pass_d)) + 1
    has_next = np.zeros(len(pb.pass_d), bool)
    has_next[:-1] = pb.pass_ind[1:] == pb.pass_ind[:-1]
    k = np.flatnonzero(has_next)
    end = np.where(pb.pass_k[k] % 2 == 0, pb.pass_start[k] + pb.pass_count[k] - 1, pb.pass_start[k])
    nk = nxt[k]
    start = np.where(pb.pass_k[k] % 2 == 0, pb.pass_start[nk] + pb.pass_count[nk] - 1,
                     pb.pass_start[nk])
    dist = np.linalg.norm(pb.p[start] - pb.p[end], axis=-1)
    return np.bincount(pb.pass_ind[k], weights=dist, minlength=pb.n)


def machining_time(path_length, feed_rate) -> np.ndarray:
    """Time in minutes: path length (mm) / feed rate (mm/min)."""
    return np.asarray(path_length, float) / float(feed_rate)


def travel_order(pb: PatternBatch, individual: int = 0) -> np.ndarray:
    """Indices of one individual's CC points in machining order (odd passes reversed)."""
    out = []
    for k in np.flatnonzero(pb.pass_ind == individual):
        idx = np.arange(pb.pass_start[k], pb.pass_start[k] + pb.pass_count[k])
        out.append(idx[::-1] if pb.pass_k[k] % 2 else idx)
    return np.concatenate(out) if out else np.zeros(0, int)
