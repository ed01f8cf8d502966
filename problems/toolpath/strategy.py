"""Which genes a strategy does not have, each with the reason (for one-line errors).

The strategy's settings themselves (``machine``, ``placement``, ``zoning``, ``spacing``,
``h_c``, ``delta_l``, ``feed_angle``, ``tolerance``, ``edge_overrun``, ``strategy``) are
fields of the typed specification (``spec/``).
"""

from __future__ import annotations

from .plan.zoning.methods import get_method
from .plan.zoning.methods.registry import REGISTRY

__all__ = ["absent_genes"]


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
