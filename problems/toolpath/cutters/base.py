"""The cutter abstraction and its registry.

A cutter is a solid of revolution about its axis ``a``, placed by its tip (the centre of the
end face, the APT ``GOTO`` point). A shape is one subclass of :class:`Cutter` that
implements three primitives, all batched over numpy arrays:

- :meth:`Cutter.height_jet`: the lower profile of a vertical cutter above its tip as a
  function of s = rho^2 / 2 (rho the radial distance from the axis), with its first two
  derivatives in s (inf beyond the radius R);
- :meth:`Cutter.width`: the half-width at a height above the tip;
- :meth:`Cutter.support_point`: the point of the cutting end furthest along a direction;
- :meth:`Cutter.swept_profile` (5-axis) and :meth:`Cutter.swept_side_width` (3-axis): the
  silhouette, the cross-section swept by a straight move (``silhouette.py`` for the
  torus family).

Everything else (the CC -> tip offset, the 3-axis drop-cutter, the APT statement) is written
once here on top of these primitives, so nothing outside this package branches on the
shape, and a tapered or conical cutter is one more subclass and one registry entry.

Registry: :func:`register` adds a shape under one or more names; :func:`make_cutter` builds
a cutter from (diameter, corner_radius), inferring the shape (each class says which
(D, r) it accepts with :meth:`Cutter.accepts`) and checking a given name against it.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from .effective_radius import effective_radius, effective_radius_3axis, effective_radius_lead_tilt
from .drop import drop_cutter

__all__ = ["Cutter", "CUTTERS", "register", "make_cutter", "cutter_from_tool", "cutter_names"]

CUTTERS: dict[str, type["Cutter"]] = {}
_ORDER: list[type["Cutter"]] = []


def register(*names: str):
    """Class decorator: register a :class:`Cutter` subclass under ``names`` (first = kind)."""

    def deco(cls):
        cls.kind = names[0]
        for name in names:
            CUTTERS[name] = cls
        _ORDER.append(cls)
        return cls

    return deco


def cutter_names() -> list[str]:
    """Registered names (aliases included), sorted."""
    return sorted(CUTTERS)


def make_cutter(diameter, corner_radius=None, kind: str | None = None, key: str = "cutter"):
    """A cutter from its diameter D and corner radius r (mm), the shape inferred and checked.

    ``kind`` (a registered name) is optional: without it, the first registered shape whose
    :meth:`Cutter.accepts` takes (D, r) is built; with it, (D, r) must fit that shape (a
    missing r takes the shape's default, e.g. 0 flat, D/2 ball). Errors are one-line
    ValueErrors starting with ``key``.
    """
    try:
        d = float(diameter)
    except (TypeError, ValueError):
        raise ValueError(f"{key}.diameter: expected a number, got {diameter!r}") from None
    if not (np.isfinite(d) and d > 0):
        raise ValueError(f"{key}.diameter: must be a finite number > 0, got {diameter!r}")
    if kind is not None and (not isinstance(kind, str) or kind not in CUTTERS):
        raise ValueError(f"{key}.type: expected one of {', '.join(cutter_names())}, "
                         f"got {kind!r}")
    if corner_radius is None:
        default = CUTTERS[kind].default_corner_radius(d) if kind is not None else None
        if default is None:
            raise ValueError(f"{key}.corner_radius: missing")
        corner_radius = default
    try:
        r = float(corner_radius)
    except (TypeError, ValueError):
        raise ValueError(f"{key}.corner_radius: expected a number, got {corner_radius!r}") from None
    if not (np.isfinite(r) and 0 <= r <= d / 2 * (1 + 1e-12)):
        raise ValueError(f"{key}.corner_radius: must be in [0, D/2 = {d / 2:g}], got {r:g}")
    r = min(r, d / 2)
    shape = next((c for c in _ORDER if c.accepts(d, r)), None)
    if shape is None:  # pragma: no cover - the registered shapes cover 0 <= r <= D/2
        raise ValueError(f"{key}: no registered cutter shape takes D {d:g}, r {r:g}")
    if kind is not None and CUTTERS[kind] is not shape:
        raise ValueError(f"{key}.type: {kind!r} does not match D {d:g}, r {r:g} "
                         f"(that is a {shape.kind} cutter)")
    return shape(d, r)


def cutter_from_tool(tool, key: str = "tool"):
    """The cutter of a tool database entry (anything with ``diameter``, ``corner_radius`` and
    optionally ``type``, e.g. ``tools.Tool``)."""
    return make_cutter(tool.diameter, tool.corner_radius, getattr(tool, "type", None), key)


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


class Cutter(ABC):
    """A cutter of diameter D and corner radius r (mm); see the module docstring."""

    kind: str = "cutter"
    #: True if the end face meets the side in a sharp edge (r = 0): fed with the bottom
    #: inclined across the feed, the rim leaves the saw-tooth "undercut" of Fountas et al.
    #: (after Bedi et al. 1996), which the criteria report separately.
    sharp_rim: bool = False

    def __init__(self, diameter: float, corner_radius: float):
        if not type(self).accepts(diameter, corner_radius):
            raise ValueError(f"cutter: D {diameter:g}, r {corner_radius:g} is not a "
                             f"{type(self).kind} cutter")
        self.diameter = float(diameter)
        self.corner_radius = float(corner_radius)

    # -- the shape: subclasses ---------------------------------------------------------
    @classmethod
    @abstractmethod
    def accepts(cls, diameter: float, corner_radius: float) -> bool:
        """True if (D, r) is this shape (used to infer the shape)."""

    @classmethod
    def default_corner_radius(cls, diameter: float) -> float | None:
        """r implied by the shape's name alone (None: r must be given)."""
        return None

    @abstractmethod
    def height_jet(self, s):
        """(g, dg/ds, d2g/ds2): lower-profile height above the tip at s = rho^2 / 2, (k,) each;
        g = inf beyond the radius."""

    @abstractmethod
    def width(self, h):
        """Half-width (mm) of the cutter at height h >= 0 above the tip; nan below the tip."""

    @abstractmethod
    def support_point(self, axis, direction):
        """Point of the cutting end furthest along ``direction`` (k, 3), relative to the tip."""

    @abstractmethod
    def swept_profile(self, lead, tilt):
        """5-axis silhouette: (x, z, reach) tables of the cross-feed profile on both sides of
        the contact for lead/tilt (radians, (k,)): rows 2j (+b side) and 2j + 1 (-b side), x
        ascending, z the height above the tangent plane, reach the last x."""

    @abstractmethod
    def swept_side_width(self, h, t_z, beta):
        """3-axis silhouette (vertical axis): lateral offset (mm) on the +b side where the
        profile rises to h above the contact; t_z the feed tangent's |z|, beta the angle of
        the cross-feed tangent to the horizontal (radians); arrays broadcast."""

    @property
    @abstractmethod
    def centre_height(self) -> float:
        """Height above the tip, on the axis, of the point a CL file may give instead of the
        tip (APT ``$$ TOOLPOINT CENTRE``)."""

    # -- written once on the primitives ------------------------------------------------
    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    def height(self, rho):
        """Lower profile of a vertical cutter above its tip at radial distance rho (inf > R)."""
        rho = np.abs(np.asarray(rho, float))
        return self.height_jet(0.5 * rho * rho)[0]

    def cc_to_tip(self, cc, normal, axis=(0.0, 0.0, 1.0)):
        """Tip that puts the cutter tangent to the surface at ``cc`` with unit normal n.

        The contact of a cutter with the tangent plane is its support point along -n, so
        tip = cc - support_point(a, -n); for the torus this is
        tip = cc + r n - (R - r) e - r a, e the unit projection of -n on the plane normal
        to a (Redonnet et al. 2013; a flat-end (r = 0) touches with its rim, a ball-end
        (R - r = 0) with its centre at cc + R n). Batched: cc, normal (k, 3); axis (3,) or
        (k, 3). Tangency is local: the tip is not gouge-free (see :meth:`drop_cutter`).
        """
        cc = np.asarray(cc, float)
        n = _unit(normal)
        a = np.broadcast_to(_unit(axis), n.shape)
        return cc - self.support_point(a, -n)

    def centre_to_tip(self, centre, axis):
        """Tips (k, 3) of CL points given as the tool centre: centre - centre_height a."""
        return np.asarray(centre, float) - self.centre_height * np.asarray(axis, float)

    def drop_cutter(self, surface, xy, return_contact: bool = False, **options):
        """Gouge-free 3-axis placement: tip z (k,) of the vertical cutter at XY (k, 2).

        The highest tip at which the cutter touches but nowhere penetrates the exact
        parametric surface: max over surface points q within R of (z_q - height(rho_q)),
        refined to ~1e-9 mm (``drop.py``). ``return_contact``: also the contact (u, v) (k, 2).
        """
        return drop_cutter(self, surface, xy, return_contact=return_contact, **options)

    def effective_radius(self, a_dot_t, a_dot_n):
        """R_eff = (R - r)(a.t)^2 / (1 - (a.n)^2)^(3/2) + r: the curvature radius at the contact
        of the cutter's silhouette projected along the feed t (a axis, n normal); inf where
        the flat bottom cuts (Redonnet et al. 2013; Djebali Sec. 2.2)."""
        return effective_radius(self.radius, self.corner_radius, a_dot_t, a_dot_n)

    def effective_radius_lead_tilt(self, lead, tilt):
        """5-axis R_eff at lead aL, tilt aT (radians): the general form with a.t = sin aL,
        a.n = cos aL cos aT: (R - r) sin^2 aL / (1 - cos^2 aL cos^2 aT)^(3/2) + r."""
        return effective_radius_lead_tilt(self.radius, self.corner_radius, lead, tilt)

    def effective_radius_3axis(self, slope, steepest, alpha):
        """3-axis R_eff (Djebali Eq. 1): (R - r) cos^2(alpha - phi) /
        (sin S (1 - sin^2(alpha - phi) sin^2 S)) + r; S slope, phi steepest direction,
        alpha feed direction (radians)."""
        return effective_radius_3axis(self.radius, self.corner_radius, slope, alpha, steepest)

    def apt_cutter(self) -> str:
        """The APT ``CUTTER/D,r`` statement (mm, 4 decimals, as the APT writer prints it)."""
        return f"CUTTER/{self.diameter:.4f},{self.corner_radius:.4f}"

    def label(self) -> str:
        return f"{self.kind} D{self.diameter:g} r{self.corner_radius:g}"

    def short_label(self) -> str:
        """Kind and D, plus r only where the shape's name does not imply it (NC comments)."""
        implied = type(self).default_corner_radius(self.diameter) is not None
        return f"{self.kind} D{self.diameter:g}" + ("" if implied else f" r{self.corner_radius:g}")

    def __repr__(self) -> str:
        return f"{type(self).__name__}(diameter={self.diameter:g}, corner_radius={self.corner_radius:g})"

    def __eq__(self, other) -> bool:
        return (type(self) is type(other) and self.diameter == other.diameter
                and self.corner_radius == other.corner_radius)

    def __hash__(self) -> int:
        return hash((type(self).__name__, self.diameter, self.corner_radius))
