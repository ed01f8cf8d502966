"""The strategy abstraction: how a zone's passes are laid out.

A :class:`Strategy` turns a batch of decision sets into a ``PlanBatch``
(``plan(planner, genes, place)``): it lays out the passes of every zone of the planner's
zone layouts, puts CC points on them (maximum step, chord tolerance) and hands them in
machining order to ``plan/finish.py``, which orients and places the tool and runs the
passes on past the part's edge the same way for every strategy. ``settings`` holds the
strategy's own keys (``KEYS``); a key of another strategy is refused in one line.
"""

from __future__ import annotations

__all__ = ["Strategy", "CurveStrategy"]

import numpy as np


class Strategy:
    """One pass layout. ``name``: the registry key; ``KEYS``: its settings and their
    defaults; ``needs_h_c``: the passes are spaced by the scallop target h_c (a plan
    without one is refused)."""

    name = ""
    KEYS: dict = {}
    needs_h_c = False

    def __init__(self, settings: dict | None = None, key: str = "strategy"):
        settings = dict(settings or {})
        unknown = sorted(set(settings) - set(self.KEYS))
        if unknown:
            from . import STRATEGIES
            owner = [n for n, s in STRATEGIES.items() if unknown[0] in s.KEYS]
            why = (f"a setting of {', '.join(owner)}, not of {self.name}" if owner
                   else f"unknown setting of {self.name} (known: "
                        f"{', '.join(self.KEYS) or 'none'})")
            raise ValueError(f"{key}.{unknown[0]}: {why}")
        self.settings = {**self.KEYS, **settings}

    def check(self, planner, key: str = "strategy") -> None:
        """ValueError naming ``key`` when the planner's configuration cannot run it."""
        if self.needs_h_c and (planner.h_c is None or not planner.h_c > 0):
            raise ValueError(f"h_c: the {self.name} strategy spaces its passes by the scallop "
                             f"target h_c (mm > 0), got {planner.h_c!r}")

    def gene_names(self, planner) -> tuple[str, ...]:
        """The decisions this strategy reads besides the machine's and the zoning's."""
        return ("tool",) + (("stepover",) if planner.spacing == "stepover" else ()) + ("step",)

    def plan(self, planner, genes: dict, place: bool):  # pragma: no cover - abstract
        raise NotImplementedError


class CurveStrategy(Strategy):
    """A strategy whose passes are curves spaced from h_c (``curves.py`` samples them):
    subclasses give :meth:`zone_passes`, the zone's pieces in machining order, memoized per
    (zone layout, tool, zone, 5-axis lead/tilt)."""

    needs_h_c = True

    def __init__(self, settings=None, key: str = "strategy"):
        super().__init__(settings, key)
        self.key = key
        self._memo: dict = {}

    def gene_names(self, planner):
        return ("tool", "step")

    def zone_passes(self, planner, layout, z, cutter, lead_tilt):  # pragma: no cover
        raise NotImplementedError

    def plan(self, planner, genes, place):
        from ..curves import plan_pieces
        from .parallel import zone_groups

        tool, n, step, _ = planner.decisions(genes)
        pieces_of = [[] for _ in range(n)]
        zones = np.ones(n, np.int64)
        for layout, rows in zone_groups(planner, genes, tool):
            zones[rows] = layout.count
            t = int(tool[rows[0]])
            if planner.machine.genes:  # 5-axis: the widths depend on each plan's lead/tilt
                lead, tilt = (np.radians(np.broadcast_to(np.asarray(genes[g], float), (n,)))
                              for g in ("lead", "tilt"))
                subsets = [((float(lead[i]), float(tilt[i])), [i]) for i in rows]
            else:
                subsets = [(None, rows)]
            for lt, sub in subsets:
                flat = []
                for z in range(layout.count):
                    mkey = (id(layout), t, z, lt)
                    if mkey not in self._memo:
                        self._memo[mkey] = self.zone_passes(planner, layout, z,
                                                            planner.tools.cutter(t), lt)
                    flat.extend(self._memo[mkey])
                for i in sub:
                    pieces_of[i] = flat
        return plan_pieces(planner, n, zones, pieces_of, tool, genes, step, place)
