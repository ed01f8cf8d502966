"""``type: choi``: Choi's bicubic Bezier test surface (Djebali et al., Table 3)."""

from __future__ import annotations

from typing import Literal

from ..bezier import choi_surface
from ..registry import SurfaceSettings, register


@register
class ChoiSettings(SurfaceSettings):
    """No settings beyond ``flip_normal``."""

    type: Literal["choi"] = "choi"

    def build(self, key: str, base_dir=None):
        return choi_surface()
