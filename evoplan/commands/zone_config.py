"""The zoning file's model (``evoplan zone CONFIG``): ``ZoneBase`` plus one settings group per
registered zoning method. Its ``tool`` is a run file's tools entry (``spec/tools.py``), so any
registered cutter zones; ``cutter: {R, r}``, the older form, still reads. Kept apart from the command so that ``evoplan zone --help`` imports
neither pydantic nor the zoning registry (scipy, scikit-learn, numba)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, create_model, field_validator

from ..config import SafeName, _Strict
from ..problems.toolpath.plan.zoning.merge import MergeSettings
from ..problems.toolpath.plan.zoning.methods import REGISTRY
from ..problems.toolpath.spec.tools import ToolSettings

#: the cutter when the file names none: Djebali's toroidal cutter, D 6.35 mm, r 1 mm
DEFAULT_TOOL = {"diameter": 6.35, "corner_radius": 1.0}


class CutterConfig(_Strict):
    """The older form of the cutter: its radius R and corner radius r (mm)."""

    R: float = 3.175
    r: float = 1.0


class ZoneBase(_Strict):
    name: SafeName = "zoning"
    surface: Any = "choi"
    tool: ToolSettings | None = Field(None, description="the cutter, as a run file's tools entry: "
                                      "{type, diameter, corner_radius, taper_angle, id, feed, "
                                      "spindle, name} (default: D 6.35 mm, r 1 mm)")
    cutter: CutterConfig | None = Field(None, description="the older form {R, r}: the same as "
                                        "tool: {diameter: 2 R, corner_radius: r}")
    h_c: float = Field(0.254, gt=0, description="the scallop height the passes keep under (mm)")
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

    def tool_settings(self) -> ToolSettings:
        """The cutter's tool entry: ``tool``, else the older ``cutter: {R, r}``, else the
        default; ValueError naming the key (the older form's checks: ``cutter.r: ...``)."""
        if self.tool is not None:
            return self.tool
        if self.cutter is None:
            return ToolSettings.model_validate(DEFAULT_TOOL)
        from ..problems.toolpath.plan.zoning.stepover import ScallopTarget

        cutter = ScallopTarget.build(self.cutter.R, self.cutter.r, self.h_c, key="cutter").cutter
        return ToolSettings(diameter=cutter.diameter, corner_radius=cutter.corner_radius)

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
