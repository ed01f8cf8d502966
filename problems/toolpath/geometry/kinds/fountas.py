"""``type: fountas``: Fountas et al.'s benchmark part (Eq. 14)."""

from __future__ import annotations

from typing import Literal

from ..registry import SurfaceSettings, register
from ..surface import fountas_surface


@register
class FountasSettings(SurfaceSettings):
    """No settings beyond ``flip_normal``."""

    type: Literal["fountas"] = "fountas"

    def build(self, key: str, base_dir=None):
        return fountas_surface()
