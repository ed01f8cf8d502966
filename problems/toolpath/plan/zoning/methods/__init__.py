"""Zoning methods: one module per method, one abstraction (``base``), one registry."""

from .base import Gene, ZoningMethod, ZoningSettings
from .registry import REGISTRY, get_method, method_names, register, unregister

__all__ = ["Gene", "REGISTRY", "ZoningMethod", "ZoningSettings", "get_method", "method_names",
           "register", "unregister"]
