"""``isoparametric``: passes along the iso-curves of the surface's parameters, spaced by the
worst point (the literature's baseline, Loney & Ozsoy 1987, cited by Djebali Sec. 1).

``curves: u`` (default) cuts the curves u = const (v running along each), ``curves: v``
the curves v = const. The first curve is the domain's edge u = 0; the next one is as far
in the parameter as the WORST point of the current curve allows: at each point the
cross-feed width w that leaves h_c (``offsets.cross_width``, the model of the other
strategies) over the surface distance one unit of the parameter moves across the curve
(|S_u . b|, b the unit cross-feed tangent), the smallest ratio of the curve, narrowed in
3-axis until the two curves' real sweeps leave at most h_c between them (a torus's sides
differ, so the current curve's symmetric width alone can overshoot); the last curve lies
on the far edge u = 1. A curve is cut where it, or the next curve, lies in the
zone (the band rule), and on a trimmed face where it leaves the footprint (a hole, a
notch: its ends there lie on the part's edge), whose points alone space it. Iso-parametric passes ignore the feed direction of the zone: on
curved patches they are longer than iso-scallop passes (Zou et al. measure 9-22 %).
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import minimum_filter1d

from ...geometry.footprint import footprint_of
from ..curves import Piece
from .base import CurveStrategy
from .isoscallop import zigzag
from .offsets import cross_width, cusp_heights, pass_frame, runs, zone_mask

__all__ = ["IsoParametric", "iso_passes"]


def iso_passes(planner, layout, z, cutter, h_c, lead_tilt=None, along="u", samples=257,
               max_passes=5000):
    """[[Piece]] per iso-curve of zone z (u = const when ``along`` is ``u``)."""
    surface = planner.surface
    fp = footprint_of(surface)
    s = np.linspace(0.0, 1.0, samples)
    fixed = 0 if along == "u" else 1

    def curve(x):
        uv = np.empty((samples, 2))
        uv[:, fixed], uv[:, 1 - fixed] = x, s
        return uv

    out, x, k = [], 0.0, 0
    while k < max_passes:
        uv = curve(x)
        jet, n, t, b = pass_frame(surface, uv)
        s_dir = jet.su if fixed == 0 else jet.sv
        across = np.einsum("ij,ij->i", s_dir, b)
        b *= np.where(across >= 0, 1.0, -1.0)[:, None]
        across = np.abs(across)
        w = cross_width(surface, cutter, h_c, jet, t, b, lead_tilt)
        on = np.ones(samples, bool) if fp.whole else fp.contains(uv[:, 0], uv[:, 1])
        last = x >= 1.0 - 1e-12
        ratio = (w / np.maximum(across, 1e-12))[on if on.any() else slice(None)]
        dx = 0.0 if last else float(np.min(ratio))
        if lead_tilt is None and not last:
            dx = _checked_step(surface, cutter, h_c, uv, jet.p, curve, x, dx, b, on)
        x_next = min(x + dx, 1.0)
        here = zone_mask(layout.labels, z, uv)
        band = here
        gap, cross = np.zeros(samples), np.zeros((samples, 3))
        if not last:
            nxt = curve(x_next)
            p_new = surface.jet(nxt[:, 0], nxt[:, 1], order=0).p
            dxy = p_new[:, :2] - jet.p[:, :2]
            gap = np.linalg.norm(dxy, axis=1)
            cross[:, :2] = dxy / np.maximum(gap, 1e-300)[:, None]
            band = here | zone_mask(layout.labels, z, nxt)
        pieces = [Piece(uv[a:e], cross[a:e], gap[a:e], z, k, layout.alpha[z],
                        (a == 0 or not on[a - 1], e == samples or not on[e]))
                  for a, e in runs(band & on) if e - a >= 2]
        if pieces:
            out.append(pieces)
        if last:
            break
        x, k = x_next, k + 1
    return out


def _checked_step(surface, cutter, h_c, uv, p, curve, x, dx, b, on, rounds=4, reach=4):
    """3-axis: the step dx to the next curve narrowed until the two curves' real sweeps
    (``offsets.cusp_heights``) leave at most h_c between them. The symmetric width of the
    current curve alone misjudges a torus: its two sides differ (corner arc uphill, flat
    bottom downhill) and the next curve's facing side is the narrower one where the slope
    steepens from curve to curve (Choi's surface, torus r 1: 0.30 mm at x 40 mm between
    the curves at x 37.2 and 40.7 mm, h_c 0.254). Checked on the part away from a run's
    ends (``reach`` samples), where the run-on past the edge, not the sweep along the
    curve, finishes the cut."""
    keep = minimum_filter1d(on, 2 * reach + 3, mode="constant", cval=False)
    if not keep.any():
        return dx
    for _ in range(rounds):
        nxt = curve(min(x + dx, 1.0))
        gap = np.linalg.norm(surface.jet(nxt[:, 0], nxt[:, 1], order=0).p - p, axis=1)
        cusp = cusp_heights(surface, cutter, uv, nxt, b, gap, reach=reach)
        worst = float(np.max(cusp[keep]))
        if worst <= h_c:
            break
        dx *= np.sqrt(h_c / worst)
    return dx


class IsoParametric(CurveStrategy):
    name = "isoparametric"
    KEYS = {"curves": "u"}

    def __init__(self, settings=None, key="strategy"):
        super().__init__(settings, key)
        if self.settings["curves"] not in ("u", "v"):
            raise ValueError(f"{key}.curves: expected u or v, got {self.settings['curves']!r}")

    def zone_passes(self, planner, layout, z, cutter, lead_tilt):
        return zigzag(iso_passes(planner, layout, z, cutter, planner.h_c, lead_tilt,
                                 self.settings["curves"]))
