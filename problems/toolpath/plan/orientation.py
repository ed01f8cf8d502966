"""Tool orientation and placement: CC points in, tool axes and CL points (tips) out.

One abstraction, one registry (``MACHINES``), batched over points:

- ``5axis``: the axis leans from the surface normal n in the travel frame (t the unit travel
  direction, b = n x t): a lead angle aL about the cross-feed axis, then a tilt aT about
  the feed (Fountas et al., Fig. 1 and Sec. 2):

      a = sin aL t + cos aL sin aT b + cos aL cos aT n

  and the tip puts the cutter tangent to the surface at the CC point
  (``Cutter.cc_to_tip``). Genes: ``lead`` and ``tilt`` (degrees).
- ``3axis``: the axis is +z. Placement ``cc``: the tip that makes the vertical cutter
  tangent to the surface at the CC point (``Cutter.cc_to_tip``; where the surface curves
  more than the cutter nearby, that tool gouges it). Placement ``drop`` (default): the same
  XY, with the height of the drop-cutter there (``Cutter.drop_cutter``: the highest tip at
  which the cutter touches the exact surface and nowhere penetrates it), so the tool is
  gouge-free and touches at the CC point wherever the tangent tool did not gouge. The
  tool's XY is the tangent tool's, not the CC point's: on a slope a vertical cutter touches
  with its uphill side, so a tool centred above the CC point would touch up to R uphill of
  it and leave a strip of width ~R uncut along every downhill edge of the part. No genes.
"""

from __future__ import annotations

import numpy as np

from ..geometry.vectors import cross_rows, row_norms, take_rows

__all__ = ["MACHINES", "Machine", "FiveAxis", "ThreeAxis", "travel_tangent", "get_machine"]


def travel_tangent(normal, alpha, reverse, rows=None) -> np.ndarray:
    """Unit travel direction on the surface at each point: the section tangent of the plane
    with cross-feed c = (-sin alpha, cos alpha, 0), t = c x n normalized (along +f), negated
    where the section is travelled along -f. normal (N, 3); alpha, reverse (N,), or per
    section with ``rows`` (N,) each point's section (the same numbers)."""
    c = np.column_stack([-np.sin(alpha), np.cos(alpha), np.zeros_like(alpha)])
    reverse = np.asarray(reverse, bool)
    if rows is not None:
        c, reverse = take_rows(c, rows), take_rows(reverse, rows)
    t = cross_rows(c, normal)
    t /= row_norms(t)[:, None]
    return np.where(reverse[:, None], -t, t)


class Machine:
    """How a machine orients and places the tool. ``genes``: the decisions it adds;
    ``overrun``: whether sections ending on the part's edge run on past it
    (``overrun.py``); ``drop``: whether the tool's height comes from the drop-cutter (its
    moves are then checked at their own XY); ``bends``: whether its run past the edge
    follows the surface's curvature along the travel (``tips``' ``bend``)."""

    name = ""
    genes: tuple[str, ...] = ()
    overrun = True
    drop = False
    bends = False

    @property
    def wedge(self) -> bool:
        """Whether a section's run past the edge also covers the wedge of part between it
        and its neighbouring planes where the edge is oblique (``sections.edge_runs``): only
        where the tool's height comes from the drop-cutter. A 5-axis tool running on along
        its tangent past an oblique edge sweeps the part's corner (0.31 mm simulated gouge,
        torus D16 r3 at 172 deg on Fountas' part)."""
        return self.drop

    def axes(self, normal, tangent, genes: dict, ind) -> np.ndarray:
        """Unit tool axes (N, 3) from normals and travel tangents (N, 3), the genes of the
        plans (n,) and each point's plan ``ind`` (N,)."""
        raise NotImplementedError

    def tips(self, cutter, surface, cc, normal, axis, shift=None, bend=None) -> np.ndarray:
        """CL points (k, 3) of one cutter's CC points (k, 3), moved by ``shift`` (k, 3)
        (None: not moved): the run past an edge (``overrun.py``); ``bend`` (k,): the
        surface's normal curvature along the travel at the CC point (1/mm, > 0 concave),
        given only to a machine that ``bends``."""
        raise NotImplementedError


class FiveAxis(Machine):
    name = "5axis"
    genes = ("lead", "tilt")
    bends = True

    def __init__(self, placement: str | None = None):
        if placement not in (None, "cc"):
            raise ValueError(f"placement: a 5-axis tool is placed tangent at the CC point "
                             f"(cc), got {placement!r}")

    def axes(self, normal, tangent, genes, ind):
        """a = sin(lead) t + cos(lead) sin(tilt) (n x t) + cos(lead) cos(tilt) n; the
        angles' functions per plan, then taken per point (the same products)."""
        lead = np.radians(np.asarray(genes["lead"], float))
        tilt = np.radians(np.asarray(genes["tilt"], float))
        per_plan = np.stack([np.sin(lead), np.cos(lead) * np.sin(tilt),
                             np.cos(lead) * np.cos(tilt)], axis=1)
        k = take_rows(per_plan, ind)
        b = cross_rows(normal, tangent)
        return k[:, :1] * tangent + k[:, 1:2] * b + k[:, 2:] * normal

    def tips(self, cutter, surface, cc, normal, axis, shift=None, bend=None):
        """The tangent tips; a shift moves them with the end point's axis: the run past an
        edge follows the travel tangent, and where the surface is concave along it
        (``bend`` > 0) the osculating parabola, lifted off the tangent by bend s^2 / 2
        along the normal at a distance s. Along the straight tangent a pass that meets the
        edge obliquely sweeps the wedge of part beside it below the surface (Fountas'
        part, torus D16 r3, lead 10, an iso-scallop plan: 0.222 mm of gouge, none without
        its run-on moves; along the parabola 0.0064 mm, 0.5 mm grid)."""
        tip = cutter.cc_to_tip(cc, normal, axis)
        if shift is None:
            return tip
        if bend is not None:
            s2 = np.einsum("ij,ij->i", shift, shift)
            shift = shift + normal * (0.5 * np.maximum(bend, 0.0) * s2)[:, None]
        return tip + shift


class ThreeAxis(Machine):
    name = "3axis"
    PLACEMENTS = ("drop", "cc")

    def __init__(self, placement: str | None = None):
        placement = placement or "drop"
        if placement not in self.PLACEMENTS:
            raise ValueError(f"placement: expected one of {', '.join(self.PLACEMENTS)}, "
                             f"got {placement!r}")
        self.placement = placement
        self.drop = placement == "drop"
        self.overrun = self.drop  # the tangent placement stays the analytic model's reference

    def axes(self, normal, tangent, genes, ind):
        return np.broadcast_to(np.array([0.0, 0.0, 1.0]), normal.shape).copy()

    def tips(self, cutter, surface, cc, normal, axis=None, shift=None, bend=None):
        """The tangent tool's XY plus the shift, dropped onto the part (placement ``cc``:
        the tangent tip plus the shift)."""
        tangent_tip = cutter.cc_to_tip(cc, normal, (0.0, 0.0, 1.0))
        if shift is None:
            shift = np.zeros_like(tangent_tip)
        if self.placement == "cc":
            return tangent_tip + shift
        xy = tangent_tip[:, :2] + shift[:, :2]
        z = cutter.drop_cutter(surface, xy)
        for scale in (0.5, 0.25, 0.0):  # a shift past a corner can leave the part's reach
            lost = ~np.isfinite(z)
            if not lost.any():
                break
            xy[lost] = tangent_tip[lost, :2] + scale * shift[lost, :2]
            z[lost] = cutter.drop_cutter(surface, xy[lost])
        return np.column_stack([xy, z])


MACHINES = {"5axis": FiveAxis, "3axis": ThreeAxis}


def get_machine(name, placement: str | None = None) -> Machine:
    """The registered machine ``name`` (``5axis`` or ``3axis``); ValueError naming ``machine``."""
    if name not in MACHINES:
        raise ValueError(f"machine: expected one of {', '.join(MACHINES)}, got {name!r}")
    return MACHINES[name](placement)
