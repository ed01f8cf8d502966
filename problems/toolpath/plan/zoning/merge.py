"""Merging zones after any zoning method: a minimum zone area, then Djebali's Eq. 4.

Why (measured on Choi's surface, 70 x 70 mesh, AMAS k_CMD = 1, k_LZ = 0.15): the AMAS
settles with 24-27 zones, seven of them of 1-7 cells, and the Eq. 4 total (2456 mm) is worse
than one zone (1669 mm). Two readings of the paper explain it:

- Djebali's agents never see Delta L: k_LZ stands in for it ("k_LZ = 0.15, equivalent to a
  40 mm Delta L", Sec. 6.4) through LZ = size / |M|, a count of meshes. On a 70 x 70 mesh
  the LZ term of every zone under a few hundred meshes is almost the same (1 - size/|M| is
  0.9998 for one cell and 0.94 for 300), so in the weighted score
  -max(k_CMD gamma/pi, k_LZ (1 - LZ)) a zone's size hardly matters: growth is stopped by the
  direction sector alone (gamma about (k_LZ / k_CMD) pi = 27 deg) and nothing makes a small
  zone pay for its Delta L. On a surface whose steepest direction turns through 180 deg
  (Choi's saddle), that is a ring of 27-deg wedges.
- The 1-3 cell zones all sit where the slope is under 1 deg (the saddle's flat centre), whose
  steepest direction is noise. Djebali Sec. 3.2 says such meshes can be machined in any
  direction, but the agents ignore the slope (Sec. 5.2.1, "for the sake of simplicity"), so
  no neighbouring sector accepts them.

The fix, a post-process any method can use (``MergeSettings``, in ``plan.plan_zones``):

1. **Minimum zone area** (``min_zone_area``, a fraction of the surface area): while a zone is
   smaller, it joins the 4-adjacent zone that costs least. The cost is the growth of the
   zones' slope-weighted misalignment: with w = area * sin(slope) per cell and
   C_z = sum over z of w exp(2 i theta) (theta the cell's optimal feed direction), the least
   sum of w sin^2(theta - alpha) over a zone is (W_z - |C_z|) / 2 (at alpha = arg(C_z) / 2),
   so merging a and b costs (|C_a| + |C_b| - |C_a + C_b|) / 2 >= 0: zero for zones with the
   same mean direction, small for flat cells (w ~ 0, Djebali's "any direction" meshes). It
   is closed form: no path is planned.
2. **Eq. 4 merging** (``by_length``): the objective the agents only approximate. Two adjacent
   zones a, b are merged when Lg(a u b) < Lg(a) + Lg(b) + Delta L, each Lg at its own
   optimized direction (Djebali Eq. 4), the most profitable pair first, until no merge
   shortens the total. This makes Delta L, not k_LZ, decide how many zones pay off.

Merging two 4-connected adjacent zones gives a 4-connected zone, so labels stay connected.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from .features import MeshFeatures

__all__ = ["MergeSettings", "merge_small_zones", "merge_by_length", "merge_zones",
           "zone_adjacency", "relabel"]


class MergeSettings(BaseModel):
    """The post-process after the zoning method (module doc)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    min_zone_area: float = Field(0.02, ge=0, lt=1, description=(
        "smallest zone, as a fraction of the surface area; smaller zones join the neighbour "
        "whose slope-weighted misalignment grows least (0: off)"))
    by_length: bool = Field(True, description=(
        "then merge adjacent zones while that shortens the Djebali Eq. 4 total "
        "(cutting length + (|Z| - 1) Delta L)"))


def relabel(labels: np.ndarray) -> np.ndarray:
    """Zone ids 0..Z-1 in first-occurrence order of a C-order scan."""
    _, first, inv = np.unique(labels, return_index=True, return_inverse=True)
    rank = np.argsort(np.argsort(first))
    return rank[inv].reshape(labels.shape).astype(np.int64)


def zone_adjacency(labels: np.ndarray) -> set[tuple[int, int]]:
    """Pairs (a < b) of zones that share a cell side."""
    a = np.concatenate([labels[1:, :].ravel(), labels[:, 1:].ravel()])
    b = np.concatenate([labels[:-1, :].ravel(), labels[:, :-1].ravel()])
    k = a != b
    lo, hi = np.minimum(a[k], b[k]), np.maximum(a[k], b[k])
    return set(zip(lo.tolist(), hi.tolist()))


class _Groups:
    """Union of the zones of ``labels``: members and adjacency of the merged groups."""

    def __init__(self, labels: np.ndarray):
        self.labels = relabel(np.asarray(labels))
        self.members = {z: frozenset([z]) for z in range(int(self.labels.max()) + 1)}
        self.pairs = zone_adjacency(self.labels)

    def neighbours(self, g: int) -> set[int]:
        out = set()
        for a, b in self.pairs:
            if a == g:
                out.add(b)
            elif b == g:
                out.add(a)
        return out

    def merge(self, keep: int, gone: int) -> None:
        self.members[keep] = self.members[keep] | self.members.pop(gone)
        self.pairs = {(min(a, b), max(a, b)) for a, b in
                      ((keep if a == gone else a, keep if b == gone else b) for a, b in self.pairs)
                      if a != b}

    def result(self) -> np.ndarray:
        owner = np.empty(self.labels.max() + 1, np.int64)
        for g, ids in self.members.items():
            owner[list(ids)] = g
        return relabel(owner[self.labels])


def merge_small_zones(labels: np.ndarray, features: MeshFeatures,
                      min_fraction: float) -> np.ndarray:
    """Merge every zone under ``min_fraction`` of the surface area (step 1 of the module doc).

    The smallest zone goes first, into the 4-adjacent zone of least misalignment cost
    (|C_a| + |C_b| - |C_a + C_b|) / 2; repeated until every zone is large enough or one is left.
    """
    groups = _Groups(labels)
    lab = groups.labels.ravel()
    nz = len(groups.members)
    area = np.bincount(lab, features.area.ravel(), nz)
    w = (features.area * np.sin(features.slope)).ravel()
    phase = np.exp(2j * features.optimal_feed.ravel())
    c = (np.bincount(lab, w * phase.real, nz) + 1j * np.bincount(lab, w * phase.imag, nz))
    limit = min_fraction * float(features.area.sum())
    while len(groups.members) > 1:
        small = [g for g in groups.members if area[g] < limit]
        if not small:
            break
        g = min(small, key=lambda z: (area[z], z))
        nb = sorted(groups.neighbours(g))
        cost = [(abs(c[g]) + abs(c[h]) - abs(c[g] + c[h])) / 2 for h in nb]
        h = nb[int(np.argmin(cost))]
        groups.merge(h, g)
        area[h] += area[g]
        c[h] += c[g]
    return groups.result()


def merge_by_length(labels: np.ndarray, zone_length: Callable[[np.ndarray], float],
                    delta_l: float) -> tuple[np.ndarray, int]:
    """Greedy Eq. 4 merging (step 2 of the module doc): (labels, zone lengths evaluated).

    ``zone_length(mask)`` is Lg of the cells ``mask`` (n, m) at its optimized direction.
    """
    groups = _Groups(labels)
    cache: dict[frozenset, float] = {}

    def length(ids: frozenset) -> float:
        if ids not in cache:
            cache[ids] = float(zone_length(np.isin(groups.labels, list(ids))))
        return cache[ids]

    while len(groups.members) > 1:
        best = None
        for a, b in sorted(groups.pairs):
            ma, mb = groups.members[a], groups.members[b]
            gain = length(ma | mb) - length(ma) - length(mb) - delta_l
            if best is None or gain < best[0]:
                best = (gain, a, b)
        if best[0] >= 0:
            break
        groups.merge(best[1], best[2])
    return groups.result(), len(cache)


def merge_zones(labels: np.ndarray, features: MeshFeatures, settings: MergeSettings | None,
                delta_l: float, zone_length: Callable[[np.ndarray], float]) -> tuple[np.ndarray, dict]:
    """Both steps as ``settings`` asks: (labels, info with the zone counts after each step)."""
    info = {"zones_in": int(labels.max()) + 1}
    if settings is None:
        return labels, info
    if settings.min_zone_area > 0:
        labels = merge_small_zones(labels, features, settings.min_zone_area)
        info["zones_after_min_area"] = int(labels.max()) + 1
    if settings.by_length:
        labels, info["length_evaluations"] = merge_by_length(labels, zone_length, delta_l)
        info["zones_after_length"] = int(labels.max()) + 1
    return labels, info
