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

- :meth:`Cutter.pieces`: the solid as a union of convex pieces of revolution (a cylinder,
  a torus or sphere, a cone frustum), which the cut simulation's numba kernels intersect
  with rays (:meth:`Cutter.kernel_params`: their shape codes and parameters in one array).

Everything else (the CC -> tip offset, the 3-axis drop-cutter, the reach of a tilted
cutter, the APT statement, the record written in every output) is written once here on
top of these primitives, so nothing outside this package branches on the shape, and a
tapered or conical cutter is one more subclass and one registry entry.

Registry: :func:`register` adds a shape under one or more names; :func:`make_cutter` builds
a cutter from (diameter, corner_radius) and the shape's own parameters (``taper_angle``),
inferring the shape (each class says which it accepts with :meth:`Cutter.accepts`) and
checking a given name against it; :func:`cutter_from_apt` from an APT ``CUTTER/`` statement.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from ..checks import number
from .effective_radius import effective_radius, effective_radius_3axis, effective_radius_lead_tilt
from .drop import drop_cutter
from .profile_kernel import CONE, CYLINDER, PIECE, ROUND
from .silhouette import support_profile_tables, support_side_width

__all__ = ["CONE", "CYLINDER", "PIECE", "ROUND", "Cutter", "CUTTERS", "register", "make_cutter", "cutter_from_tool", "cutter_names",
           "cutter_from_apt", "cutter_from_dict"]


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


def make_cutter(diameter, corner_radius=None, kind: str | None = None, key: str = "cutter",
                **extra):
    """A cutter from its diameter D and corner radius r (mm), the shape inferred and checked.

    ``kind`` (a registered name) is optional: without it, the first registered shape that
    takes exactly the given parameters (``extra``: a shape's own, e.g. ``taper_angle``) and
    whose :meth:`Cutter.accepts` takes them is built; with it, they must fit that shape (a
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
    named = CUTTERS[kind] if kind is not None else None
    extra = {k: v for k, v in extra.items() if v is not None}
    if named is not None:
        for name in named.extra_parameters:
            if name not in extra:
                raise ValueError(f"{key}.{name}: missing (a {named.kind} cutter needs it)")
        for name in sorted(set(extra) - set(named.extra_parameters)):
            raise ValueError(f"{key}.{name}: a {named.kind} cutter has no {name}")
    values = {name: number(v, f"{key}.{name}") for name, v in extra.items()}
    if corner_radius is None:
        default = named.default_corner_radius(d) if named is not None else None
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
    family = [c for c in _ORDER if set(c.extra_parameters) == set(values)]
    if named is not None:
        named.check(d, r, key, **values)  # the shape's own one-line errors
    shape = next((c for c in family if c.accepts(d, r, **values)), None)
    if shape is None:
        if values and not family:
            raise ValueError(f"{key}: no registered cutter shape takes "
                             f"{', '.join(sorted(values))}")
        if family:
            family[0].check(d, r, key, **values)
        raise ValueError(f"{key}: no registered cutter shape takes D {d:g}, r {r:g}")
    if named is not None and named is not shape:
        raise ValueError(f"{key}.type: {kind!r} does not match D {d:g}, r {r:g} "
                         f"(that is a {shape.kind} cutter)")
    return shape(d, r, **values)


def cutter_from_tool(tool, key: str = "tool"):
    """The cutter of a tool database entry (anything with ``diameter``, ``corner_radius`` and
    optionally ``type`` and a shape's own parameters, e.g. ``tools.Tool``)."""
    cutter = getattr(tool, "cutter", None)
    if isinstance(cutter, Cutter):
        return cutter
    extra = {}
    for c in _ORDER:
        for name in c.extra_parameters:
            if getattr(tool, name, None) is not None:
                extra[name] = getattr(tool, name)
    return make_cutter(tool.diameter, tool.corner_radius, getattr(tool, "type", None), key,
                       **extra)


def cutter_from_dict(record: dict, key: str = "cutter"):
    """The cutter of a record written by :meth:`Cutter.to_dict` (``type``, ``diameter``,
    ``corner_radius`` and the shape's own parameters)."""
    if not isinstance(record, dict):
        raise ValueError(f"{key}: expected a mapping, got {record!r}")
    rest = {k: v for k, v in record.items() if k not in ("type", "diameter", "corner_radius")}
    return make_cutter(record.get("diameter"), record.get("corner_radius"), record.get("type"),
                       key, **rest)


def cutter_from_apt(values, key: str = "CUTTER"):
    """The cutter of an APT ``CUTTER/d,r,e,f,a,b,h`` statement (1 to 7 values, mm and
    degrees): the first registered shape whose :meth:`Cutter.from_apt` reads it; one-line
    ValueError when none does."""
    v = [float(x) for x in values]
    if not 1 <= len(v) <= 7:
        raise ValueError(f"{key} needs 1 to 7 values, got {len(v)}")
    tapered = len(v) > 5 and v[5] != 0  # a side angle: d is measured at the tip's plane
    if v[0] <= 0 or (len(v) > 1 and not 0 <= v[1] <= (np.inf if tapered else v[0] / 2 * (1 + 1e-9))):
        raise ValueError(f"{key} needs d > 0 and 0 <= r <= d/2" if not tapered else
                         f"{key} needs d > 0 and r >= 0")
    for shape in _ORDER:
        cutter = shape.from_apt(v)
        if cutter is not None:
            return cutter
    raise ValueError(f"{key}/{','.join(f'{x:g}' for x in v)}: no registered cutter shape "
                     f"has these parameters (d,r,e,f,a,b,h)")


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
    #: True if the cutting end is a sphere about the centre (``centre_height`` up the axis):
    #: its swept profile is a circle of radius R on every slope, and turning the axis about
    #: the centre keeps the cut
    spherical: bool = False
    #: the parameters of the shape beyond D and r (each a keyword of the constructor, of
    #: :func:`make_cutter` and of a tool entry), e.g. ``("taper_angle",)``
    extra_parameters: tuple[str, ...] = ()

    def __init__(self, diameter: float, corner_radius: float, **extra):
        if not type(self).accepts(diameter, corner_radius, **extra):
            raise ValueError(f"cutter: D {diameter:g}, r {corner_radius:g} is not a "
                             f"{type(self).kind} cutter")
        self.diameter = float(diameter)
        self.corner_radius = float(corner_radius)
        for name in self.extra_parameters:
            setattr(self, name, float(extra[name]))
        self._kernel = None

    # -- the shape: subclasses ---------------------------------------------------------
    @classmethod
    @abstractmethod
    def accepts(cls, diameter: float, corner_radius: float, **extra) -> bool:
        """True if (D, r) and the shape's own parameters are this shape (used to infer it)."""

    @classmethod
    def check(cls, diameter: float, corner_radius: float, key: str, **extra) -> None:
        """One-line ValueError (starting with ``key``) when the parameters cannot make this
        shape, saying why; the torus family needs nothing beyond the registry's checks."""

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
    def pieces(self) -> list[tuple]:
        """The solid as a union of convex pieces of revolution for the cut simulation's
        kernels (``simulation/kernel.py``): tuples (code, parameters...) with the codes
        ``CYLINDER`` (w_lo), ``ROUND`` (e, c, q) and ``CONE`` (w_a, sin b, cos b, w_lo, w_hi)
        in the tool frame (w up the axis from the tip); the shank first."""

    @property
    @abstractmethod
    def cutting_height(self) -> float:
        """Height above the tip of the top of the cutting end: above it the cutter is the
        cylindrical shank of radius R."""

    def swept_profile(self, lead, tilt):
        """5-axis silhouette: (x, z, reach) tables of the cross-feed profile on both sides of
        the contact for lead/tilt (radians, (k,)): rows 2j (+b side) and 2j + 1 (-b side), x
        ascending, z the height above the tangent plane, reach the last x. By default from
        the support points (``silhouette.support_profile_tables``)."""
        return support_profile_tables(self, lead, tilt)

    def swept_side_width(self, h, t_z, beta):
        """3-axis silhouette (vertical axis): lateral offset (mm) on the +b side where the
        profile rises to h above the contact; t_z the feed tangent's |z|, beta the angle of
        the cross-feed tangent to the horizontal (radians); arrays broadcast. By default
        from the support points (``silhouette.support_side_width``)."""
        return support_side_width(self, h, t_z, beta)

    @property
    @abstractmethod
    def centre_height(self) -> float:
        """Height above the tip, on the axis, of the point a CL file may give instead of the
        tip (APT ``$$ TOOLPOINT CENTRE``)."""

    def apt_parameters(self) -> tuple[float, ...]:
        """The APT ``CUTTER/d,r,e,f,a,b,h`` values (mm, degrees): d the diameter, r the
        corner radius, (e, f) the corner centre's distance from the axis and height above
        the tip, a the bottom's angle to the horizontal, b the side's angle to the axis, h
        the height of the cutting end; the torus family: (D, r, R - r, r, 0, 0, r)."""
        return (self.diameter, self.corner_radius, self.radius - self.corner_radius,
                self.corner_radius, 0.0, 0.0, self.cutting_height)

    @classmethod
    def from_apt(cls, values) -> "Cutter | None":
        """This shape from APT ``CUTTER/`` values (1 to 7: d[,r[,e,f,a,b,h]]), or None when
        they describe another shape. The torus family: a = b = 0 and, where given, e and f
        the corner centre of (d, r) (a flat end's e and f are not looked at)."""
        d = values[0]
        r = min(values[1], d / 2) if len(values) > 1 else 0.0
        rest = list(values[2:]) + [None] * (7 - len(values))
        e, f, a, b = rest[:4]
        tol = 1e-6 * max(d, 1.0)
        if any(x is not None and abs(x) > 1e-9 for x in (a, b)):
            return None
        if r > 0 and ((e is not None and abs(e - (d / 2 - r)) > tol)
                      or (f is not None and abs(f - r) > tol)):
            return None
        return cls(d, r) if not cls.extra_parameters and cls.accepts(d, r) else None

    # -- written once on the primitives ------------------------------------------------
    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    @property
    def parameters(self) -> dict:
        """The shape's own parameters (``extra_parameters``) and their values."""
        return {name: getattr(self, name) for name in self.extra_parameters}

    def kernel_params(self) -> np.ndarray:
        """The cut simulation's kernel array: [R, n, then the n :meth:`pieces`, each in
        ``kernel.PIECE`` slots (code, parameters, zero-padded)]; cached, read-only."""
        if self._kernel is None:
            pieces = self.pieces()
            out = np.zeros(2 + PIECE * len(pieces))
            out[0], out[1] = self.radius, len(pieces)
            for k, piece in enumerate(pieces):
                out[2 + PIECE * k:2 + PIECE * k + len(piece)] = piece
            out.setflags(write=False)
            self._kernel = out
        return self._kernel

    def reach(self, sin_tilt):
        """XY distance from the tip within which the cutting end of a cutter whose axis leans
        by an angle of sine ``sin_tilt`` from the vertical lies: R + cutting height x sin."""
        return self.radius + self.cutting_height * np.asarray(sin_tilt, float)

    def ring_heights(self):
        """Heights above the tip of the rings of the lower surface that the pose gouge
        (``criteria/heel.py``) samples: the corner at 0, 20, 45 and 90 degrees from the
        bottom, h = r (1 - cos theta)."""
        return self.corner_radius * (1.0 - np.cos(np.radians([0.0, 20.0, 45.0, 90.0])))

    def to_dict(self) -> dict:
        """The cutter as written in every output (``type``, ``diameter``, ``corner_radius``,
        the shape's own parameters); :func:`cutter_from_dict` reads it back."""
        return {"type": self.kind, "diameter": self.diameter,
                "corner_radius": self.corner_radius, **self.parameters}

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
        """The APT ``CUTTER/`` statement (mm, 4 decimals, as the APT writer prints it):
        ``CUTTER/D,r`` where (D, r) say it all (the torus family), else all seven
        :meth:`apt_parameters`."""
        values = self.apt_parameters()
        if type(self).from_apt(values[:2]) == self:
            values = values[:2]
        return "CUTTER/" + ",".join(f"{v:.4f}" for v in values)

    def label(self) -> str:
        extra = "".join(f" {_SHORT.get(k, k)}{v:g}" for k, v in self.parameters.items())
        return f"{self.kind} D{self.diameter:g} r{self.corner_radius:g}{extra}"

    def short_label(self) -> str:
        """Kind and D, plus r only where the shape's name does not imply it (NC comments)."""
        implied = type(self).default_corner_radius(self.diameter) is not None
        extra = "".join(f" {_SHORT.get(k, k)}{v:g}" for k, v in self.parameters.items())
        return (f"{self.kind} D{self.diameter:g}"
                + ("" if implied else f" r{self.corner_radius:g}") + extra)

    def _key(self):
        return (type(self).__name__, self.diameter, self.corner_radius,
                *self.parameters.values())

    def __repr__(self) -> str:
        extra = "".join(f", {k}={v:g}" for k, v in self.parameters.items())
        return (f"{type(self).__name__}(diameter={self.diameter:g}, "
                f"corner_radius={self.corner_radius:g}{extra})")

    def __eq__(self, other) -> bool:
        return isinstance(other, Cutter) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())


#: short names of the shapes' own parameters in labels
_SHORT = {"taper_angle": "taper "}
