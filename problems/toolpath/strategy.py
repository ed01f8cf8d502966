"""The machining strategy of a toolpath problem, from plain data: the ``Planner`` it builds.

Keys (a run file's ``problem.params``): ``machine`` (``5axis`` | ``3axis``), ``placement``
(3-axis: ``drop`` | ``cc``), ``zoning`` ({method, mesh, merge, settings, seed}), ``spacing``
(``stepover`` | ``scallop``), ``h_c`` (mm), ``delta_l`` (mm, Djebali Eq. 4), ``feed_angle``
(degrees from +X, or ``optimized``: each zone's direction optimized), ``tolerance`` (chord
tolerance, mm), ``edge_overrun`` (true: passes run on past the part's edges,
``plan/overrun.py``). Every error is one line naming the key.
"""

from __future__ import annotations

from pydantic import ValidationError

from .checks import number
from .plan.planner import Planner
from .plan.zones import DEFAULT_H_C, ZoningSpec
from .plan.zoning.features import check_mesh
from .plan.zoning.merge import MergeSettings
from .plan.zoning.methods import get_method
from .plan.zoning.methods.base import one_line
from .plan.zoning.methods.registry import REGISTRY

__all__ = ["DEFAULT_H_C", "ZONING_KEYS", "parse_zoning", "build_planner", "absent_genes"]

ZONING_KEYS = ("method", "mesh", "merge", "settings", "seed")


def parse_zoning(spec, delta_l: float, key: str = "zoning") -> ZoningSpec | None:
    """``zoning: {method, mesh, merge, settings, seed}`` -> ``ZoningSpec`` (None: one zone).

    ``merge``: the merging post-process's settings (``MergeSettings``), ``false`` for none;
    ``settings``: the method's fixed settings (its gene's setting comes from the genes).
    """
    if spec is None:
        return None
    if isinstance(spec, str):
        spec = {"method": spec}
    if not isinstance(spec, dict):
        raise ValueError(f"{key}: expected a mapping {{method, mesh, merge, settings, seed}}, "
                         f"got {spec!r}")
    unknown = sorted(set(spec) - set(ZONING_KEYS))
    if unknown:
        raise ValueError(f"{key}.{unknown[0]}: unknown setting (known: {', '.join(ZONING_KEYS)})")
    method = get_method(spec.get("method", "single"), f"{key}.method")
    settings = spec.get("settings") or {}
    if not isinstance(settings, dict):
        raise ValueError(f"{key}.settings: expected a mapping, got {settings!r}")
    gene = method.gene
    if gene is not None and gene.setting in settings:
        raise ValueError(f"{key}.settings.{gene.setting}: set by the gene {gene.name} (fix it "
                         f"with fixed: {{{gene.name}: {settings[gene.setting]!r}}})")
    try:
        checked = method.settings(settings).model_dump(exclude_unset=True)
    except ValueError as e:
        raise ValueError(f"{key}.settings.{str(e).removeprefix(method.name + '.')}") from None
    mesh = spec.get("mesh", (70, 70))
    if not isinstance(mesh, (list, tuple)) or len(mesh) != 2:
        raise ValueError(f"{key}.mesh: expected two integers [n, m], got {mesh!r}")
    mesh = check_mesh(*mesh, key=f"{key}.mesh")
    merge = spec.get("merge", {})
    if merge is False or merge is None:
        merge = None
    else:
        if merge is True:
            merge = {}
        try:
            merge = MergeSettings.model_validate(merge)
        except ValidationError as e:
            raise ValueError(one_line(e, f"{key}.merge")) from None
    seed = spec.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"{key}.seed: expected an integer >= 0, got {seed!r}")
    return ZoningSpec(method=method.name, settings=checked, mesh=mesh, merge=merge,
                      delta_l=delta_l, seed=seed)


def parse_feed_angle(value, key: str = "feed_angle") -> float | None:
    """Degrees from +X, or None for ``optimized`` (each zone's direction, Herraz Eq. 3)."""
    if value == "optimized":
        return None
    if isinstance(value, str):
        raise ValueError(f"{key}: expected a number of degrees or optimized, got {value!r}")
    return number(value, key)


def build_planner(surface, tools, *, machine="5axis", placement=None, zoning=None,
                  spacing="stepover", h_c=None, delta_l=40.0, feed_angle=0.0, tolerance=0.01,
                  max_rounds=6, edge_overrun=True, strategy=None) -> Planner:
    """The planner of a strategy given as plain data (see the module doc); ``strategy``:
    the pass layout, ``NAME`` or {name: NAME, ...settings} (``plan/strategies``; None:
    parallel)."""
    delta_l = number(delta_l, "delta_l")
    if delta_l < 0:
        raise ValueError(f"delta_l: must be >= 0 mm, got {delta_l!r}")
    if spacing == "scallop" and h_c is None:
        h_c = DEFAULT_H_C
    if h_c is not None:
        h_c = number(h_c, "h_c", positive=True)
    if placement is not None and machine != "3axis":
        raise ValueError(f"placement: only a 3-axis machine has a placement choice "
                         f"(machine is {machine!r})")
    return Planner(surface, tools, machine=machine, placement=placement,
                   zoning=parse_zoning(zoning, delta_l), spacing=spacing, h_c=h_c,
                   tolerance=number(tolerance, "tolerance", positive=True),
                   feed_angle=parse_feed_angle(feed_angle), max_rounds=int(max_rounds),
                   edge_overrun=_flag(edge_overrun, "edge_overrun"), strategy=strategy)


def _flag(value, key: str) -> bool:
    if not isinstance(value, bool):
        raise ValueError(f"{key}: expected true or false, got {value!r}")
    return value


def absent_genes(machine: str, spacing: str, method: str, strategy: str = "parallel"
                 ) -> dict[str, str]:
    """Genes a configuration does not have, each with the reason (for one-line errors)."""
    out = {}
    if strategy != "parallel":
        out["stepover"] = f"strategy {strategy} spaces its passes from h_c"
    if machine != "5axis":
        out.update(lead=f"machine {machine} has no lead/tilt", tilt=f"machine {machine} has "
                   "no lead/tilt")
    if spacing != "stepover" and "stepover" not in out:
        out["stepover"] = f"spacing {spacing} sets the step-over from h_c"
    for other in REGISTRY.values():
        if other.gene is not None and other.name != method and other.gene.name not in out:
            out[other.gene.name] = (f"zoning method {method} has no gene" if
                                    get_method(method).gene is None else
                                    f"zoning method {method}'s gene is {get_method(method).gene.name}")
    return out
