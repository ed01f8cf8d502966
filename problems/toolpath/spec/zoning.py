"""A run file's ``zoning``: the zoning method (a registry entry) with its settings.

``zoning: NAME`` or ``{method, mesh, merge, settings, seed}``: ``method`` a registered zoning
method (``plan/zoning/methods``), ``settings`` that method's own settings model (its gene's
setting comes from the genes, never from here), ``mesh`` the parametric mesh ``[n, m]``,
``merge`` the merging post-process's settings (``false``: none), ``seed`` of any randomness.
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, model_validator

from ..plan.zones import ZoningSpec
from ..plan.zoning.features import check_mesh
from ..plan.zoning.merge import MergeSettings
from ..plan.zoning.methods import REGISTRY, get_method
from .errors import HERE
from .fields import WholeNumber

__all__ = ["ZoningSettings"]


def _method(value):
    return get_method(value, HERE).name


def _mesh(value):
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise ValueError(f"{HERE}: expected two integers [n, m], got {value!r}")
    return check_mesh(*value, key=HERE)


def _merge(value):
    if value is False or value is None:
        return None
    return {} if value is True else value


class ZoningSettings(BaseModel):
    """How a plan is zoned (see the module doc)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    method: Annotated[str, BeforeValidator(_method),
                      Field(description="a registered zoning method: " + ", ".join(REGISTRY))] = "single"
    mesh: Annotated[tuple[int, int], BeforeValidator(_mesh),
                    Field(description="the parametric mesh [n, m] the zones are made on")] = (70, 70)
    merge: Annotated[MergeSettings | None, BeforeValidator(_merge)] = Field(
        default_factory=MergeSettings, description="the merging post-process (false: none)")
    settings: dict[str, Any] = Field(default_factory=dict,
                                     description="the method's own settings")
    seed: WholeNumber = Field(0, description="seed of the method's randomness")

    @model_validator(mode="before")
    @classmethod
    def _named(cls, data):
        return {"method": data} if isinstance(data, str) else data

    @model_validator(mode="after")
    def _method_settings(self):
        method, gene = get_method(self.method), get_method(self.method).gene
        if gene is not None and gene.setting in self.settings:
            raise ValueError(f"{HERE}.settings.{gene.setting}: set by the gene {gene.name} (fix "
                             f"it with fixed: {{{gene.name}: {self.settings[gene.setting]!r}}})")
        try:
            method.settings(self.settings)
        except ValueError as e:
            raise ValueError(f"{HERE}.settings.{str(e).removeprefix(method.name + '.')}") from None
        return self

    def zoning_spec(self, delta_l: float) -> ZoningSpec:
        """The planner's :class:`~..plan.zones.ZoningSpec` (Eq. 4's ``delta_l`` for the merging)."""
        method = get_method(self.method)
        checked = method.settings(self.settings).model_dump(exclude_unset=True)
        return ZoningSpec(method=method.name, settings=checked, mesh=tuple(self.mesh),
                          merge=self.merge, delta_l=delta_l, seed=self.seed)
