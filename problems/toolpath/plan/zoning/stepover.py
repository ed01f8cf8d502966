"""Step-over of a 3-axis cutter along a feed direction, from R_eff and the surface curvature.

For every sample and a horizontal feed direction alpha (radians from +X) this module gives
the largest distance between two adjacent parallel planes that keeps the scallop height
under h_c at that sample (Djebali et al. Sec. 2.3; Herraz et al. Sec. 3).

1. Effective radius (``Cutter.effective_radius_3axis``): Djebali Eq. 1 for the toroidal
   cutter in 3-axis (exact, tool axis z):
   R_eff = (R - r) cos^2(alpha - phi) / (sin S (1 - sin^2(alpha - phi) sin^2 S)) + r; R for
   the ball-end (r = R). Horizontal ground under a torus gives R_eff = inf (the flat cuts).
2. Curvature across the feed: kappa = II(b, b) / I(b, b) along the cross-feed surface tangent
   b (the tangent orthogonal to the feed tangent t), > 0 concave seen from the tool.
3. Spacing of the contact points ON THE SURFACE, measured across the feed: the circle model
   with exact flat-surface geometry and the curvature to first order (docs/toolpath_formulas.md,
   "Scallop height"; it replaces Djebali Eq. 2, which is the spacing of the tool centres):

       w^2 = 4 h_c (2 - h_c / R_eff) / (1 / R_eff - kappa)

   which is exact on a plane (w = 2 sqrt(2 R h - h^2)) and gives sqrt(8 h R rho / (rho +- R))
   for small h on a convex / concave section. Where 1/R_eff <= kappa (a concave section at
   least as tight as the effective circle) the circle model predicts no cusp.
4. Physical cap: a cutter cannot leave a cusp lower than h_c farther apart than its own width
   at height h_c (``Cutter.width``), w_cap = 2 ((R - r) + sqrt(2 r h_c - h_c^2)) (2R when
   h_c >= r): the flat bottom plus the corner arc, the widest cut the tool makes on any
   plane (5.68 mm for R = 3.175, r = 1, h_c = 0.254). w = min(w_circle, w_cap) everywhere.
5. Plane spacing: the passes are vertical planes, so the spacing used to place them is the
   horizontal component of w b across the feed: d = w (b . c) / |b|, c = (-sin a, cos a).

Accuracy: R_eff (a circle) is within a few per cent of a simulated cut for the ball-end and
only approximate (15-30 %) for toroidal cutters, whose swept profile is an offset ellipse
(docs/toolpath_formulas.md); the cap is exact on planes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...checks import number
from ...cutters import Cutter, make_cutter
from .profile import profile_width
from .samples import SurfaceSamples

__all__ = ["ScallopTarget", "plane_spacing"]


@dataclass(frozen=True)
class ScallopTarget:
    """A 3-axis finish: the cutter (a :class:`~..cutters.Cutter`, axis z) and the scallop
    height h_c (mm) its passes must keep under. The geometry is the cutter's."""

    cutter: Cutter
    h_c: float

    @classmethod
    def build(cls, R, r, h_c, key: str = "cutter") -> "ScallopTarget":
        """Checked constructor from the radius R, corner radius r and h_c: R > 0,
        0 <= r <= R, h_c > 0 (ValueError naming the key)."""
        R = number(R, f"{key}.R", positive=True)
        r = number(r, f"{key}.r")
        h = number(h_c, f"{key}.h_c", positive=True)
        if not 0 <= r <= R:
            raise ValueError(f"{key}.r: the corner radius must be in [0, R = {R}], got {r}")
        return cls(make_cutter(2 * R, r, key=key), h)

    @property
    def width_cap(self) -> float:
        """Widest CC spacing with a cusp <= h_c on any plane: twice the cutter's half-width
        at h_c, 2 ((R - r) + sqrt(2 r h_c - h_c^2)) (2 R when h_c >= r)."""
        return float(2 * self.cutter.width(self.h_c))


def plane_spacing(s: SurfaceSamples, target: ScallopTarget, alpha: float,
                  model: str = "profile") -> np.ndarray:
    """Largest horizontal distance (mm) between parallel planes along ``alpha`` keeping the
    scallop <= h_c at each sample: (N,). ``model``: "circle" (R_eff, Djebali Eq. 1) or
    "profile" (the exact swept profile, ``profile.py``). See the module docstring."""
    fx, fy = np.cos(alpha), np.sin(alpha)
    p, q = s.p, s.q
    w2 = 1.0 + p * p + q * q
    # cross-feed tangent in xy parameters: beta orthogonal to the feed in the metric I
    gx = fx * (1 + p * p) + fy * p * q
    gy = fx * p * q + fy * (1 + q * q)
    bx, by = -gy, gx  # beta . c = gx fx + gy fy > 0 since I is positive definite
    bz = p * bx + q * by
    b2 = bx * bx + by * by + bz * bz
    kappa = (bx * bx * s.hxx + 2 * bx * by * s.hxy + by * by * s.hyy) / (np.sqrt(w2) * b2)
    across = (bx * -fy + by * fx) / np.sqrt(b2)  # (b . c) / |b|
    if model == "profile":
        t_z = (p * fx + q * fy) / np.sqrt(1 + (p * fx + q * fy) ** 2)
        w = profile_width(target, t_z, bz / np.sqrt(b2), kappa)
        return np.minimum(w, target.width_cap) * across
    r_eff = target.cutter.effective_radius_3axis(s.slope, s.steepest, alpha)
    inv_r = 1.0 / r_eff  # 0 where R_eff = inf
    h = target.h_c
    margin = inv_r - kappa
    with np.errstate(divide="ignore", invalid="ignore"):
        w_circle = np.where(margin > 0, np.sqrt(4 * h * (2 - h * inv_r) / margin), np.inf)
    return np.minimum(w_circle, target.width_cap) * across
