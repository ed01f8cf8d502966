"""Surfaces from plain data (a YAML ``params:`` ``surface`` value): the registry's front door.

``surface`` is a type name (``"fountas"``, ``"choi"``) or a mapping with ``type`` and that
type's settings; every type is one module in ``kinds/`` (see ``registry.py``), and control
nets come from ``nets.py``. Errors are one-line ``ValueError`` starting with the key path.
"""

from __future__ import annotations

from .nets import MAX_NET_BYTES, load_poles
from .registry import SURFACES, parse_surface

__all__ = ["parse_surface", "load_poles", "MAX_NET_BYTES", "SURFACES"]
