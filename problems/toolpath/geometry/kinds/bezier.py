"""``type: bezier``: a tensor-product Bezier net, ``poles`` (p+1, q+1, 3), optional ``degree``."""

from __future__ import annotations

from typing import Any, Literal

from ..bezier import BezierSurface
from ..nets import check_net, load_net, parse_degree
from ..registry import SurfaceSettings, register


@register
class BezierSettings(SurfaceSettings):
    """``poles``: a net or its file (``nets.py``); ``degree`` [p, q] fixes the net's shape."""

    type: Literal["bezier"] = "bezier"
    poles: Any
    degree: Any = None

    def build(self, key: str, base_dir=None):
        net = load_net(self.poles, f"{key}.poles", base_dir)
        expected = None
        if self.degree is not None:
            p, q = parse_degree(self.degree, f"{key}.degree")
            expected = (p + 1, q + 1, 3)
        check_net(net, f"{key}.poles", expected)
        return BezierSurface(net)
