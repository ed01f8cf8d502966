"""The surface registry: one settings model per surface type, validated once, built on demand.

A surface type is one module in ``kinds/`` holding a pydantic settings model (a subclass of
:class:`SurfaceSettings` whose ``type`` is a ``Literal``) registered with :func:`register`;
its :meth:`SurfaceSettings.build` returns the :class:`Surface`. Nothing outside ``geometry/``
branches on a surface's type: :func:`parse_surface` looks the type up here, validates the
mapping with its model and builds it; ``surface_union()`` is the discriminated union the typed
toolpath specification embeds.

Optional for every type: ``flip_normal: true`` (the tool side is opposite to the default,
which is the side with +z at the domain centre).

Errors are ``ValueError`` with one line starting with the key path, e.g.
``surface.weights: must be > 0 (first at [1][2])``.
"""

from __future__ import annotations

from typing import Annotated, ClassVar, Union

from pydantic import BaseModel, ConfigDict, Field, StrictBool, ValidationError

from .surface import Surface
from .surface_checks import check_height_field

__all__ = ["SURFACES", "SurfaceSettings", "register", "parse_surface", "settings_for",
           "surface_union", "validation_line"]

SURFACES: dict[str, type["SurfaceSettings"]] = {}


class SurfaceSettings(BaseModel):
    """Base of the per-type settings models (unknown keys are errors)."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    #: check the built surface is a height field over XY (a type that checks itself sets False)
    check_graph: ClassVar[bool] = True

    flip_normal: StrictBool = False

    def build(self, key: str, base_dir=None) -> Surface:  # pragma: no cover - abstract
        """The surface these settings describe; ``ValueError`` naming ``key`` on bad data."""
        raise NotImplementedError


def register(cls: type[SurfaceSettings]) -> type[SurfaceSettings]:
    """Class decorator: add a settings model to :data:`SURFACES` under its ``type`` literal."""
    (name,) = cls.model_fields["type"].annotation.__args__
    SURFACES[name] = cls
    return cls


def validation_line(exc: ValidationError, key: str, what: str) -> str:
    """One line ``key.path: message`` from a pydantic error (all unknown keys named at once)."""
    errors = exc.errors()
    extra = [str(e["loc"][-1]) for e in errors if e["type"] == "extra_forbidden"]
    if extra:
        return f"{key}: unknown key(s) for {what}: {', '.join(sorted(extra))}"
    first = errors[0]
    loc = ".".join([key] + [str(p) if not isinstance(p, int) else f"[{p}]" for p in first["loc"]])
    loc = loc.replace(".[", "[")
    msg = first["msg"].removeprefix("Value error, ")
    if first["type"] in ("bool_type", "bool_parsing"):
        msg = "expected true or false"
    if first["type"] == "missing":
        msg = "missing"
    elif "input" in first and first["type"] != "value_error":
        msg = f"{msg}, got {first['input']!r}"
    return f"{loc}: {msg}"


def settings_for(spec, key: str = "surface") -> SurfaceSettings:
    """The validated settings of a surface given as a name or a mapping with ``type``."""
    if isinstance(spec, SurfaceSettings):
        return spec
    if isinstance(spec, str):
        spec = {"type": spec}
    if not isinstance(spec, dict):
        raise ValueError(f"{key}: expected a name or a mapping, got {spec!r}")
    kind = spec.get("type")
    if not isinstance(kind, str) or kind not in SURFACES:
        raise ValueError(f"{key}.type: expected one of {', '.join(SURFACES)}, got {kind!r}")
    try:
        return SURFACES[kind].model_validate(spec)
    except ValidationError as exc:
        raise ValueError(validation_line(exc, key, f"a {kind} surface")) from None


def parse_surface(spec, key: str = "surface", base_dir=None) -> Surface:
    """Build a surface from plain data (a name, a mapping with ``type``, or settings)."""
    if isinstance(spec, Surface):
        return spec
    settings = settings_for(spec, key)
    surf = settings.build(key, base_dir)
    if settings.check_graph:
        check_height_field(surf, key)  # no fold, overhang, vertical wall or self-overlap
    if settings.flip_normal:
        surf.normal_sign = -surf.normal_sign
    return surf


def surface_union():
    """The discriminated union (on ``type``) of every registered settings model."""
    models = tuple(SURFACES.values())
    return Annotated[Union[models], Field(discriminator="type")]


from . import kinds  # noqa: E402,F401  (registers the shipped types)
