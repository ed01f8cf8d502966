"""The zoning-method abstraction: a name, its settings (validated) and ``labels``.

A zoning method turns the per-cell features of the parametric mesh (``features.py``) into
zone labels: an (n, m) array of ids 0..Z-1, every zone 4-connected (Djebali Sec. 3.1: a zone
is a set of contiguous meshes). A method is a ``ZoningMethod`` subclass with

- ``name``: the key of the registry and of the ``method`` setting;
- ``Settings``: a strict pydantic model of its settings (unknown keys refused), whose
  defaults are the method's defaults;
- ``gene``: optionally, the setting a toolpath problem may turn into a gene (Herraz's K,
  Djebali's k_LZ) with its kind and default range;
- ``labels(features, settings, seed)``: the labels and a dict of facts about the run.

The registry (``registry.py``) holds one instance per name; ``plan.py``, the toolpath
zoning problem and the ``evoplan zone`` command only go through it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from pydantic import BaseModel, ConfigDict, ValidationError

from ....checks import interval
from ..features import MeshFeatures

__all__ = ["Gene", "ZoningMethod", "ZoningSettings", "one_line"]


class ZoningSettings(BaseModel):
    """Base of a method's settings: strict (unknown keys refused, no inf/nan)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, populate_by_name=True)


@dataclass(frozen=True)
class Gene:
    """A setting a problem may optimize: gene name, setting name, integer or real, range."""

    name: str
    setting: str
    integer: bool
    bounds: tuple[float, float]


def one_line(error: ValidationError, key: str) -> str:
    """The first error of a pydantic validation as ``key.field: message``."""
    first = error.errors()[0]
    loc = ".".join(str(p) for p in (key, *first["loc"]) if p != "")
    return f"{loc}: {first['msg'].removeprefix('Value error, ')}"


class ZoningMethod:
    """One zoning method (see the module doc); subclasses set the class attributes."""

    name: ClassVar[str] = ""
    Settings: ClassVar[type[ZoningSettings]] = ZoningSettings
    gene: ClassVar[Gene | None] = None

    def settings(self, data: Any = None, **values) -> ZoningSettings:
        """Validated settings from a mapping, a ``Settings`` instance or keywords.

        ``ValueError`` with one line ``<name>.<key>: message`` on bad input.
        """
        if isinstance(data, self.Settings) and not values:
            return data
        if isinstance(data, BaseModel):
            data = data.model_dump()
        try:
            return self.Settings.model_validate({**(data or {}), **values})
        except ValidationError as e:
            raise ValueError(one_line(e, self.name)) from None

    def gene_range(self, value, features: MeshFeatures) -> tuple[float, float]:
        """The (lo, hi) range of ``gene`` a problem asks for, checked; ValueError naming it."""
        if self.gene is None:
            raise ValueError(f"method: {self.name!r} has no setting to optimize as a gene")
        lo, hi = interval(value, self.gene.name)
        if self.gene.integer and (lo != int(lo) or hi != int(hi)):
            raise ValueError(f"{self.gene.name}: expected integers, got {list(value)!r}")
        for x in (lo, hi):
            self.settings({self.gene.setting: int(x) if self.gene.integer else x})
        return lo, hi

    def labels(self, features: MeshFeatures, settings: ZoningSettings,
               seed: int = 0) -> tuple[np.ndarray, dict]:
        """(zone ids (n, m), info dict) of the mesh; ``seed`` seeds any randomness."""
        raise NotImplementedError

    @property
    def description(self) -> str:
        """The first line of the class docstring (for help texts)."""
        return (type(self).__doc__ or self.name).strip().splitlines()[0]
