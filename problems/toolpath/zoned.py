"""``toolpath_zoning``: the former zoning problem, now a configuration of ``toolpath``.

Its parameters translate into the one problem's (:func:`zoning_config`):

    surface, tools (default: Choi's R 3.175 ball, toroidal r 1 and 1.27, flat), h_c, delta_l
    method, mesh, settings, seed, k_cmd    -> zoning: {method, mesh, settings, seed, merge: false}
    zones / k_lz / gene_ranges             -> ranges: {the method's gene: [lo, hi]}
    (implied)                              -> machine: 3axis, placement: drop, spacing: scallop,
                                              feed_angle: optimized, fixed: {step: 1},
                                              weights: {eq4_total: 1},
                                              normalization: {eq4_total: [0, 1]}

so its objective is still Djebali's Eq. 4 total in mm, its genes the tool and the zoning
gene. Errors name the old keys (``zones: ...``, ``mesh: ...``). New run files should write
``problem: toolpath`` with these settings (``runs/choi_zoning_vega.yaml``).
"""

from __future__ import annotations

import numpy as np

from .plan.zoning.methods import get_method
from .problem import ToolpathProblem

__all__ = ["ZonedToolpathProblem", "CHOI_TOOLS", "zoning_config"]

CHOI_TOOLS = [
    {"id": 1, "type": "ball", "diameter": 6.35},
    {"id": 2, "type": "toroidal", "diameter": 6.35, "corner_radius": 1.0},
    {"id": 3, "type": "toroidal", "diameter": 6.35, "corner_radius": 1.27},
    {"id": 4, "type": "flat", "diameter": 6.35},
]

#: new key prefix -> the old parameter it came from (for error messages)
_OLD_KEYS = {"ranges.": "", "zoning.mesh": "mesh", "zoning.method": "method",
             "zoning.settings": "settings", "zoning.seed": "seed", "fixed.": ""}


def zoning_config(surface="choi", tools=None, h_c=0.254, delta_l=40.0, mesh=(70, 70),
                  method="kmeans", zones=(1, 8), k_lz=(0.02, 0.6), k_cmd=1.0, seed=0,
                  stepover_model="profile", base_dir=None, settings=None,
                  gene_ranges=None) -> dict:
    """The ``toolpath`` params of a former ``toolpath_zoning`` config (module doc)."""
    zoning = get_method(method)
    if zoning.gene is None:
        raise ValueError(f"method: {method!r} has no setting to optimize as a gene")
    if stepover_model != "profile":
        raise ValueError(f"stepover_model: the toolpath engine spaces passes by the cutter's "
                         f"swept profile (profile), got {stepover_model!r}")
    fixed = dict(settings or {})
    if "k_cmd" in zoning.Settings.model_fields:
        fixed.setdefault("k_cmd", k_cmd)
    ranges = {"zones": zones, "k_lz": k_lz, **(gene_ranges or {})}
    return {
        "surface": surface, "tools": CHOI_TOOLS if tools is None else tools,
        "machine": "3axis", "placement": "drop", "spacing": "scallop", "h_c": h_c,
        "delta_l": delta_l, "feed_angle": "optimized",
        "zoning": {"method": zoning.name, "mesh": list(mesh) if isinstance(mesh, tuple) else mesh,
                   "settings": fixed, "seed": seed, "merge": False},
        "ranges": {zoning.gene.name: ranges.get(zoning.gene.name, zoning.gene.bounds)},
        "fixed": {"step": 1.0}, "weights": {"eq4_total": 1.0},
        "normalization": {"eq4_total": [0.0, 1.0]}, "base_dir": base_dir,
    }


def _old_key(message: str) -> str:
    for new, old in _OLD_KEYS.items():
        if message.startswith(new):
            return old + message[len(new):]
    return message


class ZonedToolpathProblem(ToolpathProblem):
    """Tool and zoning chosen together, minimizing the Eq. 4 length (see the module doc).

    Plain-data params as before: ``surface`` (default choi), ``tools``, ``h_c`` (0.254),
    ``delta_l`` (40), ``mesh`` ([70, 70]), ``method`` (kmeans | amas), ``zones`` range for
    kmeans ([1, 8]), ``k_lz`` range for amas ([0.02, 0.6]), ``gene_ranges``, ``settings``,
    ``k_cmd`` (1), ``seed``. ``criteria(X)`` also reports ``total_length`` (= ``eq4_total``)
    and ``penalty`` ((zones - 1) delta_l).
    """

    def __init__(self, base_dir=None, **params):
        try:
            self.config = zoning_config(base_dir=base_dir, **params)
            super().__init__(**self.config)
        except ValueError as e:
            raise ValueError(_old_key(str(e))) from None

    def criteria(self, X) -> dict[str, np.ndarray]:
        crit = super().criteria(X)
        crit["total_length"] = crit["eq4_total"]
        crit["penalty"] = (crit["zones"] - 1.0) * self.delta_l
        return crit

    def cl_path(self, params, step: float | None = None, placement: str | None = None,
                tolerance: float | None = None):
        """(CLPath, mesh labels) of one plan by name (``tool`` id and the zoning gene), with
        the CC step (mm, default 1), the 3-axis ``placement`` (drop | cc) and the chord
        ``tolerance`` optionally changed for this path."""
        if step is None and placement is None and tolerance is None:
            return super().cl_path(params)
        changed = dict(self.config)
        changed["fixed"] = {"step": 1.0 if step is None else step}
        changed["placement"] = placement or changed["placement"]
        if tolerance is not None:
            changed["tolerance"] = tolerance
        return ToolpathProblem(**changed).cl_path(params)
