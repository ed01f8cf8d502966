"""``ToolpathSpec``: a run file's toolpath ``params``, typed and validated once.

It is composed from the registries' own settings models: the surface (``geometry/registry.py``,
a discriminated union on ``type``), the tools (``spec/tools.py``, each a registered cutter),
the zoning method (``spec/zoning.py``), the pass layout (``plan/strategies``), the machine
(``plan/orientation.py``), the criteria (``criteria/table.py``), the cut simulation's
settings (``criteria/simulated.py``, with its screening's in ``criteria/screening.py``) and
the machine's dynamics (``criteria/kinematic_time.py``). :meth:`ToolpathSpec.from_params` turns plain data into the
model with a one-line ``ValueError`` that starts with the key path
(``zoning.method: expected one of single, kmeans, amas, got 'kmean'``); ``ToolpathProblem``
builds from the model. The genes' ``ranges`` and ``fixed`` values are checked here
(``spec/genes.py``); which genes exist, the zoning method's gene range and the tool ids are
checked against the configuration when the problem is built (``genes.py``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (BaseModel, BeforeValidator, ConfigDict, Field, StrictBool, ValidationError,
                      model_validator)
from pydantic.json_schema import SkipJsonSchema

from ..checks import number
from ..criteria.kinematic_time import Dynamics
from ..criteria.objective import DEFAULT_WEIGHTS, Bounds, Objectives, Weights, check_bounded
from ..criteria.screening import ScreeningSettings
from ..criteria.simulated import SimulationSettings
from ..geometry.registry import settings_for, surface_union
from ..geometry.surface import Surface
from ..plan.orientation import MACHINES
from ..plan.planner import SPACINGS
from ..plan.strategies import STRATEGIES, get_strategy
from ..plan.zones import DEFAULT_H_C
from .errors import HERE, Known, one_line
from .fields import NonNegative, Positive
from .genes import FixedGenes, GeneRanges, both_given
from .tools import ToolList
from .zoning import ZoningSettings

__all__ = ["ToolpathSpec"]

def _one_of(names, what: str):
    def check(value):
        if value not in names:
            raise ValueError(f"{HERE}: expected one of {', '.join(names)}, got {value!r}")
        return value
    check.__doc__ = f"one of the registered {what}"
    return check


def _surface(value):
    return value if isinstance(value, Surface) else settings_for(value, HERE)


def _feed_angle(value):
    if value == "optimized":
        return value
    if isinstance(value, str):
        raise ValueError(f"{HERE}: expected a number of degrees or optimized, got {value!r}")
    return number(value, HERE)


def _strategy(value):
    if isinstance(value, (list, tuple)):
        if not value:
            raise ValueError(f"{HERE}: an empty list of strategies to choose from")
        for i, item in enumerate(value):
            get_strategy(item, f"{HERE}[{i}]")
    elif value is not None:
        get_strategy(value, HERE)
    return value


def _criteria(value):
    if value not in ("analytic", "simulated"):
        raise ValueError(f"{HERE}: expected analytic or simulated, got {value!r}")
    return value


def _mapping(what: str):
    def check(value):
        if value is not None and not isinstance(value, dict):
            raise ValueError(f"{HERE}: expected a mapping {what}, got {value!r}")
        return value
    return check


def _moved_mesh(data):
    """``mesh`` directly under the params (the old form): refused, naming ``zoning: {mesh}``."""
    if not isinstance(data, dict) or "mesh" not in data:
        return data
    mesh, zoning = data["mesh"], data.get("zoning")
    method = zoning if isinstance(zoning, str) else \
        zoning.get("method") if isinstance(zoning, dict) else None
    shown = (f"[{', '.join(f'{x:g}' for x in mesh)}]" if isinstance(mesh, (list, tuple))
             and all(isinstance(x, (int, float)) for x in mesh) else repr(mesh))
    raise ValueError(f"mesh: moved under zoning (zoning: {{method: {method or 'METHOD'}, "
                     f"mesh: {shown}}})")


def _flag(value):
    if not isinstance(value, bool):
        raise ValueError(f"{HERE}: expected true or false, got {value!r}")
    return value


class ToolpathSpec(BaseModel):
    """The toolpath problem's settings (docs/toolpath-spec.md lists every key)."""

    model_config = ConfigDict(extra="forbid", frozen=True, arbitrary_types_allowed=True)

    _moved = model_validator(mode="before")(_moved_mesh)

    # the part and the tools
    surface: Annotated[surface_union() | SkipJsonSchema[Surface], BeforeValidator(_surface),
                       Field(description="the design surface: a registered type name or a "
                             "mapping with type and that type's settings")] = "fountas"
    tools: ToolList | None = Field(None, description="the tool database (default: Fountas' nine)")
    base_dir: SkipJsonSchema[str | Path | None] = Field(
        None, description="set by evoplan: the run file's folder, where relative files resolve")
    # the strategy
    machine: Annotated[str, BeforeValidator(_one_of(tuple(MACHINES), "machines")),
                       Field(description="a registered machine: " + " | ".join(MACHINES))] = "5axis"
    placement: str | None = Field(None, description="3axis only: drop | cc")
    zoning: ZoningSettings | None = Field(None, description="a zoning method's name or "
                                          "{method, mesh, merge, settings, seed} (none: one zone)")
    spacing: Annotated[str, BeforeValidator(_one_of(SPACINGS, "spacings")),
                       Field(description="stepover: the gene sets the passes' XY spacing; "
                             "scallop: spaced from h_c")] = "stepover"
    h_c: Positive | None = Field(None, description=f"scallop height, mm (scallop spacing: "
                                 f"{DEFAULT_H_C})")
    delta_l: Annotated[NonNegative, Field(description="Djebali Eq. 4 penalty per extra zone, mm")] = 40.0
    feed_angle: Annotated[float | Literal["optimized"], BeforeValidator(_feed_angle),
                          Field(description="degrees from +X, or optimized")] = 0.0
    tolerance: Annotated[Positive, Field(description="chord tolerance, mm")] = 0.01
    max_rounds: int = Field(6, description="refinement rounds of the adaptive pass spacing")
    edge_overrun: Annotated[StrictBool, BeforeValidator(_flag),
                            Field(description="passes run on past the part's edges")] = True
    border_passes: Annotated[StrictBool, BeforeValidator(_flag),
                             Field(description="a trimmed face's edges the passes leave above "
                                   "h_c are cut by border passes")] = True
    strategy: Annotated[Any, BeforeValidator(_strategy),
                        Field(description="the pass layout: " + " | ".join(STRATEGIES)
                              + ", {name, ...settings}, or a list to choose from")] = None
    # the decisions
    ranges: Annotated[GeneRanges | None, BeforeValidator(_mapping("gene -> [lo, hi]")),
                      Field(description="gene -> [lo, hi]: a free gene's range")] = None
    fixed: Annotated[FixedGenes | None, BeforeValidator(_mapping("gene -> value")),
                     Field(description="gene -> value: not a variable (the tool by its id)")] = None
    # the judgement
    weights: Annotated[Weights | None,
                       Field(description="criterion -> weight (Fountas Eq. 9; default "
                             "machining_error 0.5, cc_count 0.5)")] = None
    objectives: Annotated[Objectives | None,
                          Field(description="criteria of a multi-objective F (instead of weights)")] = None
    normalization: Annotated[Bounds | None,
                             Field(description="criterion -> [lo, hi]: given bounds ([0, 1] keeps "
                                   "the raw value); the others from a seeded design")] = None
    normalization_samples: int = Field(64, description="random rows of the normalization design")
    seed: int = Field(0, description="seed of the normalization design")
    feed_rate: Annotated[Positive, Field(description="mm/min")] = 1000.0
    allowance: Annotated[Positive, Field(description="finishing stock, mm")] = 0.5
    dynamics: Dynamics = Field(default_factory=Dynamics,
                               description="the machine's limits (the kinematic machining_time)")
    criteria: Annotated[Literal["analytic", "simulated"], BeforeValidator(_criteria),
                        Field(description="simulated: scallop, gouge and machining error "
                              "measured by the cut simulation")] = "analytic"
    simulation: Annotated[SimulationSettings | None, BeforeValidator(_mapping("of settings")),
                          Field(description="criteria: simulated only: how the cut simulation "
                                "measures a plan (the defaults when absent)")] = None

    @model_validator(mode="after")
    def _together(self):
        both_given(self.ranges, self.fixed)
        if self.placement is not None and self.machine != "3axis":
            raise ValueError(f"placement: only a 3-axis machine has a placement choice "
                             f"(machine is {self.machine!r})")
        if self.simulation is not None and self.criteria != "simulated":
            raise ValueError("simulation: only used with criteria: simulated")
        if self.normalization is not None:
            check_bounded(self.normalization, self.judged)
        return self

    # -- derived ----------------------------------------------------------------------
    @property
    def judged(self) -> list[str]:
        """The criteria F is made of: the objectives, else the weighted ones."""
        return list(self.objectives) if self.objectives is not None else list(self.weights_or_default)

    @property
    def weights_or_default(self) -> dict[str, float]:
        return dict(DEFAULT_WEIGHTS) if self.weights is None else dict(self.weights)

    @property
    def scallop_height(self) -> float | None:
        """h_c, with the scallop spacing's default when none is given (mm)."""
        return DEFAULT_H_C if self.h_c is None and self.spacing == "scallop" else self.h_c

    # -- from plain data --------------------------------------------------------------
    @classmethod
    def from_params(cls, params: dict | None = None, base_dir=None) -> "ToolpathSpec":
        """The spec of a run file's ``params`` mapping; one-line ``ValueError`` naming the key."""
        params = dict(params or {})
        if base_dir is not None:
            params.setdefault("base_dir", base_dir)
        try:
            return cls.model_validate(params)
        except ValidationError as e:
            raise ValueError(one_line(e, known_of=_known_keys)) from None

    @classmethod
    def json_schema(cls) -> dict:
        """The JSON schema of a run file's toolpath ``params`` (the docs page is made from it)."""
        return cls.model_json_schema()


def _known_keys(loc) -> list[str] | None:
    """The keys the mapping at ``loc`` may hold (for an unknown key's hint)."""
    if loc == ():
        return [k for k in ToolpathSpec.model_fields if k != "base_dir"]
    if loc[:1] == ("tools",):
        from .tools import ToolSettings
        return list(ToolSettings.model_fields)
    settings = {("simulation",): SimulationSettings,
                ("simulation", "screening"): ScreeningSettings}.get(tuple(loc))
    if settings is not None:
        return Known.settings(settings)
    model = {("zoning",): ZoningSettings, ("dynamics",): Dynamics}.get(tuple(loc))
    return None if model is None else list(model.model_fields)
