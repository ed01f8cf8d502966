"""The machining file's model (``evoplan machine CONFIG``): stock, allowances, the three
operations and the post. Kept apart from the command so that ``evoplan machine --help`` imports
no pydantic model.

The file is validated here once, when it is loaded: the post's dialect against the post
registry, the kinematics (built for a 5-axis post, as its post will hold them) and
``finish.problem`` by the toolpath specification (``ToolpathSpec``, the keys a finish plan
takes), each imported when a file is checked. A check raised inside a validator writes
``HERE`` (``problems/toolpath/spec/errors.py``) where its key path goes; :func:`evoplan.commands.machine.load` fills it in. Checks that need
built objects stay in ``problems/toolpath/roughing/operation_set.py``: the clearance plane
against the stock top (computed from the surface) and a 3-axis post refusing a 5-axis finish
plan (the plan may come from ``--from-run``).
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, field_validator, model_validator

from ..config import _Strict

#: the toolpath specification's keys a finish plan takes (``finish.problem``); the others
#: (surface, weights, objectives, normalization, simulation) do not change the one plan made
PLAN_KEYS = ("feed_rate", "tolerance", "feed_angle", "allowance", "tools", "ranges")


class ToolCfg(_Strict):
    number: int = Field(1, ge=0)
    diameter: float = Field(12.0, gt=0)
    spindle: float = Field(6000.0, gt=0)


class StockCfg(_Strict):
    top: float | None = None          # absolute; default z_max + top_offset
    top_offset: float = Field(5.0, ge=0)
    cell: float = Field(0.5, gt=0)    # Z-map and layer grid, mm


class AllowanceCfg(_Strict):
    semifinish: float = Field(0.5, ge=0)   # D_off1
    finish: float = Field(0.3, ge=0)       # D_off2


class RoughCfg(_Strict):
    method: Literal["morphing", "morphing_full", "zlevel", "contour"] = "morphing"
    tool: ToolCfg = Field(default_factory=lambda: ToolCfg(number=1, diameter=12.0, spindle=6000.0))
    max_depth: float = 2.0             # D_cut, mm
    stepover: float = Field(0.6, gt=0, le=1)   # fraction of the diameter
    feed: float = Field(800.0, gt=0)
    plunge_feed: float = Field(250.0, gt=0)
    tolerance: float = Field(0.01, gt=0)


class BallCfg(_Strict):
    tool: ToolCfg = Field(default_factory=lambda: ToolCfg(number=2, diameter=12.0, spindle=8000.0))
    stepover: float = Field(1.5, gt=0)  # mm between passes
    step: float = Field(1.0, gt=0)      # mm between points
    feed: float = Field(1000.0, gt=0)
    plunge_feed: float = Field(300.0, gt=0)


class PlanParams(_Strict):
    tool: int = 8
    stepover: float = 30.0
    lead: float = 2.0
    tilt: float = 0.0
    step: float = 6.0


class FinishCfg(BallCfg):
    source: Literal["plan", "offset"] = "plan"
    params: PlanParams = Field(default_factory=PlanParams)
    problem: dict[str, Any] = Field(default_factory=dict)   # toolpath problem params (PLAN_KEYS)

    @field_validator("problem")
    @classmethod
    def _plan_params(cls, value: dict) -> dict:
        """Only the keys of :data:`PLAN_KEYS`, each checked by ``ToolpathSpec``."""
        from ..problems.toolpath.spec import ToolpathSpec
        from ..problems.toolpath.spec.errors import HERE

        unknown = set(value) - set(PLAN_KEYS)
        if unknown:
            raise ValueError(f"{HERE}.{sorted(unknown)[0]}: unknown (known: {', '.join(PLAN_KEYS)})")
        try:
            ToolpathSpec.from_params(value)
        except ValueError as e:
            raise ValueError(f"{HERE}.{e}") from None
        return value


class RotaryCfg(_Strict):
    name: str
    about: Literal["x", "y", "z"]
    limits: list[float] = Field(min_length=2, max_length=2)


class KinematicsCfg(_Strict):
    layout: Literal["table_table", "head_table"] = "table_table"
    tilt: RotaryCfg = Field(default_factory=lambda: RotaryCfg(name="A", about="x", limits=[-30.0, 110.0]))
    rotary: RotaryCfg = Field(default_factory=lambda: RotaryCfg(name="C", about="z", limits=[-360.0, 360.0]))
    max_step: float = Field(10.0, gt=0)        # degrees per NC block (larger turns are split)
    max_deviation: float = Field(5.0, gt=0)   # degrees off the great circle before a reposition
    clearance_height: float = Field(20.0, gt=0)   # clearance plane above the stock top, mm
    clearance_plane: float | None = None       # or the plane's absolute Z (at or above the stock top)
    rotary_threshold: float = Field(20.0, gt=0)   # larger rotary turns only at the clearance plane (deg)
    pole_angle: float = Field(0.5, ge=0, lt=90)   # |tilt| below which the table holds (deg; 0: off)
    rapid_rotary: float = Field(5400.0, gt=0)     # rotary rapid rate, deg/min

    def build(self):
        """The :class:`~evoplan.problems.toolpath.export.kinematics.Kinematics` of these
        settings (a ``ValueError`` if the axes do not make a machine)."""
        from ..problems.toolpath.export.kinematics import Kinematics, Rotary

        return Kinematics(self.layout, Rotary(self.tilt.name, self.tilt.about, tuple(self.tilt.limits)),
                          Rotary(self.rotary.name, self.rotary.about, tuple(self.rotary.limits)),
                          self.max_step, self.max_deviation, self.rotary_threshold, self.pole_angle,
                          rapid_rotary=self.rapid_rotary)


class PostCfg(_Strict):
    dialect: str = "fanuc"
    work_offset: str = Field("G54", pattern=r"^G5[4-9]$")
    program_number: int = Field(1000, ge=1, le=9999)
    rapid_rate: float = Field(10000.0, gt=0)
    tolerance: float | None = Field(None, gt=0)  # mm: merge near-collinear points, fit G2/G3 (iso); None: every point
    kinematics: KinematicsCfg = Field(default_factory=KinematicsCfg)

    @field_validator("dialect")
    @classmethod
    def _known_post(cls, value: str) -> str:
        from ..problems.toolpath.export.posts import POSTS
        from ..problems.toolpath.spec.errors import HERE

        if value not in POSTS:
            raise ValueError(f"{HERE}: unknown post {value!r} (known: {', '.join(sorted(POSTS))})")
        return value

    @model_validator(mode="after")
    def _machine(self):
        """A 5-axis post's kinematics must make a machine (a 3-axis post ignores them)."""
        from ..problems.toolpath.export.posts import POSTS
        from ..problems.toolpath.spec.errors import HERE

        if POSTS[self.dialect].five_axis:
            try:
                self.kinematics.build()
            except ValueError as e:
                raise ValueError(f"{HERE}.kinematics: {e}") from None
        return self


class MachineConfig(_Strict):
    name: str = "machine"
    surface: Any = "choi"
    stock: StockCfg = Field(default_factory=StockCfg)
    allowances: AllowanceCfg = Field(default_factory=AllowanceCfg)
    roughing: RoughCfg = Field(default_factory=RoughCfg)
    semifinish: BallCfg = Field(default_factory=BallCfg)
    finish: FinishCfg = Field(default_factory=lambda: FinishCfg(
        tool=ToolCfg(number=3, diameter=12.0, spindle=10000.0), stepover=0.8, step=0.5, feed=1200.0))
    post: PostCfg = Field(default_factory=PostCfg)
