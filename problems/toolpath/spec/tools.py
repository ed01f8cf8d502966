"""A run file's ``tools``: the settings model of one tool, and the database it builds.

Each entry: ``diameter`` (> 0), ``corner_radius`` (0 <= r <= D/2; a shape that implies it,
ball or flat, may leave it out), optional ``id`` (default: position + 1), ``type`` (a
registered cutter name or alias, checked against r when given), a shape's own parameters
(``taper_angle``: the half-angle of a tapered ball's cone, degrees), ``name``, and the
cutting data ``feed`` (mm/min), ``plunge_feed`` (mm/min), ``spindle`` (rpm): an entry with
any of them needs its ``feed``. The shape is the registered cutter
:func:`~..cutters.make_cutter` infers from these; the result is the one :class:`~..tools.Tool`.
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import (AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field,
                      TypeAdapter, ValidationError, model_validator)

from ..cutters import CUTTERS, cutter_names, make_cutter
from ..tools import DEFAULT_TOOLS, Tool, ToolDatabase
from .errors import HERE, one_line
from .fields import Number, Positive

__all__ = ["ToolSettings", "ToolList", "tool_database", "parse_tools", "tool_from_text",
           "TOOL_TEXT"]

#: the command-line form of one tool (``evoplan simulate --nc FILE --tool ...``)
TOOL_TEXT = "[TYPE:]D[,r][,NAME=VALUE...]"


def _cutter_type(value):
    if value is not None and (not isinstance(value, str) or value not in CUTTERS):
        raise ValueError(f"{HERE}: expected one of {', '.join(cutter_names())}, got {value!r}")
    return value


def _tool_id(value):
    if value is not None and (isinstance(value, bool) or not isinstance(value, int)):
        raise ValueError(f"{HERE}: expected an integer, got {value!r}")
    return value


def _renamed_key(data):
    """An entry written with the old keys ``R`` / ``r`` (radii): refused, naming the new key."""
    if not isinstance(data, dict):
        return data
    for old, new, factor in (("R", "diameter", 2.0), ("r", "corner_radius", 1.0)):
        if old not in data:
            continue
        value = data[old]
        form = f"{new} = 2R" if factor != 1 else new
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            form += f" ({old}: {value:g} is {new}: {factor * value:g})"
        raise ValueError(f"{HERE}.{old}: renamed {form}")
    return data


class ToolSettings(BaseModel):
    """One tool of the database (see the module doc)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    id: Annotated[int | None, BeforeValidator(_tool_id),
                  Field(description="the tool number (default: position + 1)")] = None
    type: Annotated[str | None, BeforeValidator(_cutter_type),
                    Field(description="a registered cutter: " + ", ".join(sorted(CUTTERS)))] = None
    diameter: Annotated[Number, Field(description="D, mm (> 0)")]
    corner_radius: Number | None = Field(None, description="r, mm (0 <= r <= D/2; a ball or "
                                         "flat type implies it)")
    taper_angle: Number | None = Field(None, description="degrees: a tapered ball's cone half-angle")
    name: str = Field("", description="shown in reports and NC comments")
    feed: Positive | None = Field(None, description="mm/min (the kinematic time and the NC "
                                  "program; needed with plunge_feed or spindle)")
    plunge_feed: Positive | None = Field(None, description="mm/min")
    spindle: Positive | None = Field(None, description="rpm")

    _renamed = model_validator(mode="before")(_renamed_key)

    @model_validator(mode="after")
    def _shape(self):
        d, r = self.diameter, self.corner_radius
        if d <= 0:
            raise ValueError(f"{HERE}.diameter: must be > 0, got {d:g}")
        if r is not None and r < 0:
            raise ValueError(f"{HERE}.corner_radius: must be >= 0, got {r:g}")
        if r is not None and r > d / 2 + 1e-12:
            raise ValueError(f"{HERE}.corner_radius: {r:g} exceeds the tool radius {d / 2:g}")
        rates = [k for k in ("plunge_feed", "spindle") if getattr(self, k) is not None]
        if rates and self.feed is None:
            raise ValueError(f"{HERE}.feed: missing (an entry with {', '.join(rates)} needs its "
                             f"feed, mm/min)")
        self.cutter()  # the shape inferred, a given type checked
        return self

    def cutter(self):
        """The registered cutter these settings describe."""
        return make_cutter(self.diameter, self.corner_radius, self.type, key=HERE,
                           taper_angle=self.taper_angle)

    def tool(self, position: int) -> Tool:
        """The :class:`~..tools.Tool` (the id defaults to ``position + 1``)."""
        extra = {} if self.spindle is None else {"spindle": self.spindle}
        return Tool(position + 1 if self.id is None else self.id, self.cutter(),
                    feed=self.feed, plunge_feed=self.plunge_feed, name=self.name, **extra)


def _non_empty_list(value):
    if not isinstance(value, (list, tuple)) or len(value) == 0:
        raise ValueError(f"{HERE}: expected a non-empty list of tools, got {value!r}")
    return list(value)


def _unique_ids(tools: list[ToolSettings]) -> list[ToolSettings]:
    ids = [t.id if t.id is not None else i + 1 for i, t in enumerate(tools)]
    dup = sorted({x for x in ids if ids.count(x) > 1})
    if dup:
        raise ValueError(f"{HERE}: duplicate tool id(s) {', '.join(map(str, dup))}")
    return tools


#: ``tools``: a non-empty list of tools with unique ids
ToolList = Annotated[list[ToolSettings], BeforeValidator(_non_empty_list),
                     AfterValidator(_unique_ids)]

_TOOLS = TypeAdapter(ToolList)


def tool_database(tools: list[ToolSettings] | None) -> ToolDatabase:
    """The database of validated tool settings (None: the default nine, ``tools.py``)."""
    if tools is None:
        tools = _TOOLS.validate_python(DEFAULT_TOOLS)
    return ToolDatabase([t.tool(i) for i, t in enumerate(tools)])


def parse_tools(spec: Any = None, key: str = "tools") -> ToolDatabase:
    """The database of a plain ``tools`` list (None: the default nine), validated by
    :data:`ToolList`; one-line ``ValueError`` starting with ``key``, e.g.
    ``tools[2].corner_radius: 9 exceeds the tool radius 8``."""
    if spec is None:
        return tool_database(None)
    try:
        return tool_database(_TOOLS.validate_python(spec))
    except ValidationError as e:
        raise ValueError(one_line(e, key)) from None


def tool_from_text(text: str, key: str = "--tool") -> Tool:
    """One tool from the command-line form :data:`TOOL_TEXT`: an optional registered cutter
    type, the diameter D and corner radius r (mm; r = 0 when neither r nor a type is given),
    then a shape's own parameters by name, e.g. ``12,6`` (a ball), ``12`` (a flat end),
    ``toroidal:16,3`` or ``tapered_ball:8,1,taper_angle=10``. One-line ``ValueError``
    starting with ``key``."""
    hint = f"give {TOOL_TEXT}, e.g. 12,6 or tapered_ball:8,1,taper_angle=10"
    kind, _, rest = str(text).rpartition(":")
    parts = [p.strip() for p in rest.split(",")]
    named = dict(p.split("=", 1) for p in parts if "=" in p)
    sizes = [p for p in parts if "=" not in p]
    if not 1 <= len(sizes) <= 2 or any(p.partition("=")[0] in ("", "type") for p in named):
        raise ValueError(f"{key} {text!r}: {hint}")
    try:
        values = [float(x) for x in sizes] + [float(v) for v in named.values()]
    except ValueError:
        raise ValueError(f"{key} {text!r}: {hint}") from None
    data = {"diameter": values[0], **dict(zip(named, values[len(sizes):]))}
    if kind:
        data["type"] = kind
    if len(sizes) == 2:
        data["corner_radius"] = values[1]
    elif not kind:
        data["corner_radius"] = 0.0
    try:
        return ToolSettings.model_validate(data).tool(0)
    except ValidationError as e:
        raise ValueError(f"{key} {text!r}: {one_line(e, 'tool')} ({hint})") from None
