"""mkdocs hook: tables of every key of evoplan's run and study files, from the pydantic models.

A line ``<!-- keys: module:Model prefix -->`` in a page becomes a table of the model's fields
(nested groups flattened to dotted keys under ``prefix``; ``top``: the model's own keys
only): key, type, default, meaning.
``<!-- keys: algorithms -->`` makes one table per algorithm of ``evoplan.config.REGISTRY``;
``<!-- keys: surfaces -->`` one per surface type of the toolpath surface registry and
``<!-- keys: zoning_methods -->`` one per zoning method's settings.
The tables are generated when the site is built, so they always list the keys the code accepts.
"""

from __future__ import annotations

import importlib
import json
import re
import typing

from pydantic import BaseModel
from pydantic_core import PydanticUndefined

MARKER = re.compile(r"^<!-- keys: (\S+)(?: (\S+))? -->$", re.M)


def _type(annotation) -> str:
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is typing.Annotated:
        return _type(args[0])
    if annotation is typing.Any:
        return "any"
    if origin is typing.Literal:
        return " \\| ".join(f"`{a}`" for a in args)
    if origin in (typing.Union, getattr(__import__("types"), "UnionType", None)):
        tags = [a.model_fields["type"].annotation for a in args
                if isinstance(a, type) and issubclass(a, BaseModel) and "type" in a.model_fields]
        if len(tags) > 1:  # a discriminated union: its tags
            return "one of " + ", ".join(f"`{typing.get_args(t)[0]}`" for t in tags)
        return " or ".join(_type(a) for a in args if a is not type(None)) + (
            " or null" if type(None) in args else "")
    if origin in (list, tuple):
        return f"list of {_type(args[0])}" if args else "list"
    if origin is dict:
        return "mapping"
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return "group"
    return getattr(annotation, "__name__", str(annotation)).replace("NoneType", "null")


def _default(field) -> str:
    if field.default_factory is not None:
        value = field.default_factory()
    elif field.default is PydanticUndefined:
        return "required"
    else:
        value = field.default
    if isinstance(value, BaseModel):
        return "(group)"
    return f"`{json.dumps(value, default=str)}`"


def _bounds(field) -> str:
    """``>= 2``, ``in (0, 1]``... from the field's constraints."""
    marks = {"ge": ">=", "gt": ">", "le": "<=", "lt": "<"}
    parts = [f"{sign} {getattr(m, key)}" for m in field.metadata for key, sign in marks.items()
             if getattr(m, key, None) is not None]
    return ", ".join(parts)


def rows(model: type[BaseModel], prefix: str, nest: bool = True) -> list[str]:
    out = []
    for name, field in model.model_fields.items():
        key = f"{prefix}.{name}" if prefix else name
        annotation = field.annotation
        nested = annotation if isinstance(annotation, type) and issubclass(annotation, BaseModel) else None
        text = "; ".join(t for t in (field.description or "", _bounds(field)) if t).replace("|", "\\|")
        out.append(f"| `{key}` | {_type(annotation)} | {_default(field)} | {text} |")
        if nested is not None and nest:
            out.extend(rows(nested, key))
    return out


def table(model: type[BaseModel], prefix: str) -> str:
    """The table of ``model``; prefix ``top``: its own keys only, groups not expanded."""
    head = "| key | type | default | meaning |\n|---|---|---|---|\n"
    top = prefix == "top"
    return head + "\n".join(rows(model, "" if top else prefix, nest=not top)) + "\n"


def _first_line(obj) -> str:
    return (obj.__doc__ or "").strip().splitlines()[0] if obj.__doc__ else ""


def _sections(key: str, entries, prefix: str) -> str:
    """One ``#### `key: name``` section per (name, text, model) of a registry."""
    return "\n".join(f"#### `{key}: {name}`\n\n{text}\n\n{table(model, prefix)}"
                     for name, text, model in entries)


def algorithms() -> str:
    registry = importlib.import_module("evoplan.config").REGISTRY
    return _sections("algorithm.name", ((name, _first_line(cls), model)
                                        for name, (cls, model) in registry.items()), "algorithm")


def surfaces() -> str:
    registry = importlib.import_module("evoplan.problems.toolpath.geometry.registry").SURFACES
    return _sections("surface.type", ((name, _first_line(model), model)
                                      for name, model in registry.items()), "surface")


def zoning_methods() -> str:
    registry = importlib.import_module("evoplan.problems.toolpath.plan.zoning.methods").REGISTRY
    return _sections("zoning.method", (
        (name, method.description + (f" Its gene `{method.gene.name}` sets "
                                     f"`{method.gene.setting}`." if method.gene else ""),
         method.Settings) for name, method in registry.items()), "zoning.settings")


def _replace(match: re.Match) -> str:
    target, prefix = match.group(1), match.group(2) or ""
    if target in GROUPS:
        return GROUPS[target]()
    module, _, attr = target.partition(":")
    return table(getattr(importlib.import_module(module), attr), prefix)


GROUPS = {"algorithms": algorithms, "surfaces": surfaces, "zoning_methods": zoning_methods}


def on_page_markdown(markdown, page, config, files):
    return MARKER.sub(_replace, markdown)
