"""``type: nurbs``: a rational B-spline net: the ``bspline`` keys plus ``weights`` (nu, nv) > 0.

``weights`` is a nested list ``weights[i][j]`` or a file in the control-net formats
(``.json`` / ``.yaml``: the list or a mapping with a ``weights`` key; ``.csv``: rows ``i,j,w``).
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from ..nets import fail, load_net
from ..nurbs import NURBSSurface
from ..registry import register
from .bspline import BSplineSettings, net_and_knots


@register
class NurbsSettings(BSplineSettings):
    """``poles``, ``degree``, ``knots_u``, ``knots_v`` as for ``bspline``; ``weights`` required."""

    type: Literal["nurbs"] = "nurbs"
    weights: Any

    def build(self, key: str, base_dir=None):
        net, degree, tu, tv = net_and_knots(self, key, base_dir)
        wkey = f"{key}.weights"
        w = load_net(self.weights, wkey, base_dir, field="weights", width=1)
        if w.shape != net.shape[:2]:
            fail(wkey, f"expected shape {net.shape[:2]} (one weight per pole), got {w.shape}")
        bad = ~np.isfinite(w)
        if bad.any():
            i, j = np.argwhere(bad)[0]
            fail(wkey, f"contains NaN or infinite values (first at [{i}][{j}])")
        if np.any(w <= 0):
            i, j = np.argwhere(w <= 0)[0]
            fail(wkey, f"weights must be > 0, got {w[i, j]:g} at [{i}][{j}]")
        return NURBSSurface(net, w, degree, tu, tv)
