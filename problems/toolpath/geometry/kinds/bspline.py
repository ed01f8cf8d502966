"""``type: bspline``: a tensor-product B-spline net (``degree`` default [3, 3], optional knots)."""

from __future__ import annotations

from typing import Any, Literal

from ..bspline import BSplineSurface
from ..nets import check_knots, check_net, fail, load_net, parse_degree
from ..registry import SurfaceSettings, register


def net_and_knots(settings, key: str, base_dir):
    """(poles, (p, q), knots_u, knots_v) checked against each other (shared with ``nurbs``)."""
    p, q = parse_degree(settings.degree, f"{key}.degree")
    net = load_net(settings.poles, f"{key}.poles", base_dir)
    check_net(net, f"{key}.poles")
    if net.shape[0] <= p or net.shape[1] <= q:
        fail(f"{key}.poles", f"a degree ({p}, {q}) B-spline needs at least "
             f"({p + 1}, {q + 1}, 3) poles, got {net.shape}")
    tu = check_knots(settings.knots_u, net.shape[0], p, f"{key}.knots_u")
    tv = check_knots(settings.knots_v, net.shape[1], q, f"{key}.knots_v")
    return net, (p, q), tu, tv


@register
class BSplineSettings(SurfaceSettings):
    """``poles`` a net or its file; knots default to clamped uniform."""

    type: Literal["bspline"] = "bspline"
    poles: Any
    degree: Any = (3, 3)
    knots_u: Any = None
    knots_v: Any = None

    def build(self, key: str, base_dir=None):
        net, degree, tu, tv = net_and_knots(self, key, base_dir)
        return BSplineSurface(net, degree, tu, tv)
