"""The registry of zoning methods: name -> ``ZoningMethod`` instance.

A new method is one module (a ``ZoningMethod`` subclass) and one line in ``_BUILTIN`` (or a
``register`` call from user code); ``plan.py``, the toolpath zoning problem and the
``evoplan zone`` command find it here by name.
"""

from __future__ import annotations

from .amas import Amas
from .base import ZoningMethod
from .kmeans import KMeans
from .single import Single

__all__ = ["REGISTRY", "register", "unregister", "get_method", "method_names"]

_BUILTIN: tuple[type[ZoningMethod], ...] = (Single, KMeans, Amas)
REGISTRY: dict[str, ZoningMethod] = {cls.name: cls() for cls in _BUILTIN}


def register(method: ZoningMethod | type[ZoningMethod], replace: bool = False) -> ZoningMethod:
    """Add a method (an instance or a class) under its ``name``; returns the instance."""
    if isinstance(method, type):
        method = method()
    if not isinstance(method, ZoningMethod) or not method.name:
        raise TypeError("register: expected a ZoningMethod with a non-empty name")
    if method.name in REGISTRY and not replace:
        raise ValueError(f"method: {method.name!r} is already registered")
    REGISTRY[method.name] = method
    return method


def unregister(name: str) -> None:
    """Remove a method (tests that register their own clean up with it)."""
    REGISTRY.pop(name, None)


def method_names() -> tuple[str, ...]:
    return tuple(REGISTRY)


def get_method(name, key: str = "method") -> ZoningMethod:
    """The registered method ``name`` (or ``name`` itself if it is a method); ValueError."""
    if isinstance(name, ZoningMethod):
        return name
    try:
        return REGISTRY[name]
    except (KeyError, TypeError):
        raise ValueError(f"{key}: expected one of {', '.join(REGISTRY)}, got {name!r}") from None
