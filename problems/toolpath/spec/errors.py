"""One-line errors of the toolpath specification: the key path, then what is wrong.

A check called inside a validator does not know where its value sits in the run file; it
writes :data:`HERE` where the key path goes (``f"{HERE}: must be > 0"``, or
``f"{HERE}.corner_radius: ..."`` for a key below it) and :func:`one_line` puts the path of
the failing value there (``tools[2].corner_radius: ...``). Errors pydantic raises itself
(a wrong type, a missing or unknown key) get the same form from their location.
"""

from __future__ import annotations

from typing import NamedTuple

from pydantic import ValidationError

__all__ = ["HERE", "Known", "key_path", "one_line"]

#: placeholder for the key path in a message raised inside a validator
HERE = "\x1e"


class Known(NamedTuple):
    """The keys a mapping may hold, for an unknown key's hint, and what the hint calls one
    (``simulation.share: unknown setting (known: ...)``)."""

    keys: list
    noun: str = "key"

    @classmethod
    def settings(cls, model) -> "Known":
        """A settings model's keys, sorted, each an ``unknown setting`` in the hint."""
        return cls(sorted(model.model_fields), "setting")


def key_path(loc, prefix: str = "") -> str:
    """``("tools", 2, "diameter")`` -> ``tools[2].diameter`` (after ``prefix``, if any)."""
    out = prefix
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif "[" in str(part) or "," in str(part):  # a union member's tag: not a key
            continue
        else:
            out += f".{part}" if out else str(part)
    return out


def _unknown(errors, prefix: str, known_of) -> str | None:
    extra = [e for e in errors if e["type"] == "extra_forbidden"]
    if not extra:
        return None
    parent = extra[0]["loc"][:-1]
    names = sorted(str(e["loc"][-1]) for e in extra if e["loc"][:-1] == parent)
    known = known_of(parent) if known_of else None
    known = known if known is None or isinstance(known, Known) else Known(list(known))
    tail = f" (known: {', '.join(known.keys)})" if known and known.keys else ""
    noun = known.noun if known else "key"
    if len(names) == 1:
        return f"{key_path((*parent, names[0]), prefix)}: unknown {noun}{tail}"
    return f"{key_path(parent, prefix) or 'params'}: unknown {noun}s {', '.join(names)}{tail}"


def one_line(exc: ValidationError, prefix: str = "", known_of=None) -> str:
    """The first error of ``exc`` as ``key.path: message`` (every unknown key of one mapping
    named at once; ``known_of(loc)``: the keys that mapping may hold, for the hint, a list
    or a :class:`Known`)."""
    errors = exc.errors()
    unknown = _unknown(errors, prefix, known_of)
    if unknown is not None:
        return unknown
    first = errors[0]
    where = key_path(first["loc"], prefix) or "params"
    msg = first["msg"].removeprefix("Value error, ").removeprefix("Assertion failed, ")
    if HERE in msg:
        return msg.replace(HERE, where).splitlines()[0]
    if not first["loc"] and not prefix and first["type"] == "value_error":
        return msg.splitlines()[0]  # a check across keys names its own keys
    kind = first["type"]
    if kind == "missing":
        msg = "missing"
    elif kind in ("bool_type", "bool_parsing"):
        msg = "expected true or false"
    elif kind in ("model_type", "dict_type", "model_attributes_type"):
        msg = f"expected a mapping, got {first.get('input')!r}"
    elif "input" in first and kind != "value_error":
        msg = f"{msg}, got {first['input']!r}"
    return f"{where}: {msg}".splitlines()[0]
