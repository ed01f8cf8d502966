"""The zoning file's model (``evoplan zone CONFIG``): ``ZoneBase`` plus one settings group per
registered zoning method. Kept apart from the command so that ``evoplan zone --help`` imports
neither pydantic nor the zoning registry (scipy, scikit-learn, numba)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, create_model, field_validator

from ..config import SafeName, _Strict
from ..problems.toolpath.plan.zoning.merge import MergeSettings
from ..problems.toolpath.plan.zoning.methods import REGISTRY


class CutterConfig(_Strict):
    R: float = 3.175
    r: float = 1.0


class ZoneBase(_Strict):
    name: SafeName = "zoning"
    surface: Any = "choi"
    cutter: CutterConfig = Field(default_factory=CutterConfig)
    h_c: float = 0.254
    delta_l: float = 40.0
    mesh: list[int] = Field(default_factory=lambda: [70, 70], min_length=2, max_length=2)
    method: str = Field("amas", description="a registered zoning method: single, kmeans, amas")
    seed: int = 0
    merge: MergeSettings = Field(default_factory=MergeSettings)
    stepover_model: Literal["profile", "circle"] = "profile"
    sample_spacing: float = Field(0.25, gt=0)
    direction_scan: int = Field(12, ge=1)
    step: float = Field(1.0, gt=0, description="largest distance between CC points (mm)")
    strategy: Any = Field("parallel", description="the pass layout: a registered strategy "
                          "name (parallel, isoscallop, contour, isoparametric) or {name, ...settings}")

    @field_validator("method")
    @classmethod
    def _registered(cls, v: str) -> str:
        if v not in REGISTRY:
            raise ValueError(f"expected one of {', '.join(REGISTRY)}")
        return v


def zone_config_model() -> type[ZoneBase]:
    """The zoning-file model: ``ZoneBase`` plus one settings group per registered method."""
    groups = {name: (m.Settings, Field(default_factory=m.Settings, description=m.description))
              for name, m in REGISTRY.items()}
    return create_model("ZoneConfig", __base__=ZoneBase, **groups)


ZoneConfig = zone_config_model()  # the built-in methods' model (docs/zoning.md lists its keys)
