"""The registry of finishing strategies: one module and one entry per pass layout.

- ``parallel`` (``parallel.py``): vertical planes along the zone's feed, fixed step-over
  or adaptive at h_c (each plane as far as its pass's worst point allows);
- ``isoscallop`` (``isoscallop.py``): each pass offset from the previous one, point by
  point, by the cross-feed distance that leaves exactly h_c there;
- ``contour`` (``contour.py``): inward offsets of the zone's boundary, nested loops cut
  outside in, each as far as the worst point of the previous loop allows;
- ``isoparametric`` (``isoparametric.py``): u (or v) iso-curves of the surface, spaced by
  the worst point of each curve.

:func:`get_strategy` builds one from ``strategy: NAME`` and its settings; every strategy
yields the same ``PlanBatch`` (``base.py``).
"""

from __future__ import annotations

from .base import Strategy
from .contour import Contour
from .isoparametric import IsoParametric
from .isoscallop import IsoScallop
from .parallel import Parallel

__all__ = ["STRATEGIES", "Strategy", "get_strategy"]

STRATEGIES: dict[str, type[Strategy]] = {
    "parallel": Parallel, "isoscallop": IsoScallop, "contour": Contour,
    "isoparametric": IsoParametric}


def get_strategy(spec=None, key: str = "strategy") -> Strategy:
    """A strategy from a name, a mapping {name: NAME, ...settings} or a Strategy (None:
    ``parallel``); ValueError naming ``key`` for an unknown name or setting."""
    if isinstance(spec, Strategy):
        return spec
    if spec is None:
        return Parallel()
    settings = {}
    if isinstance(spec, dict):
        settings = {k: v for k, v in spec.items() if k != "name"}
        spec = spec.get("name")
    if spec not in STRATEGIES:
        raise ValueError(f"{key}: unknown strategy {spec!r} (known: {', '.join(STRATEGIES)})")
    return STRATEGIES[spec](settings, key)
