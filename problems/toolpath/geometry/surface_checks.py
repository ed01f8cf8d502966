"""Is a surface machinable from above? Refuse folds, overhangs, vertical walls and self-overlap.

The toolpath model (zig-zag planes swept in XY, tool axis near +Z, drop-cutter placement)
assumes the part is a height field over its XY footprint: every (x, y) of the footprint has one
surface point, and the normal on the tool side points upwards. A control net can describe
surfaces that are not: a fold (the net doubles back), an overhang (part of the surface faces
down), a vertical wall (the normal is horizontal), or a sheet that overlaps itself in plan view.
Evaluated anyway they give numbers that mean nothing, so they are refused with the reason.

The test samples the surface on an ``n x n`` parametric grid (first derivatives only):

- the plan-view Jacobian ``J = x_u y_v - x_v y_u`` (the signed area rate of the map
  ``(u, v) -> (x, y)``) must keep one sign: a sign change is a fold or an overhang;
- the normal's vertical component ``|n_z| = |J| / |s_u x s_v|`` must exceed ``sin(1 deg)``:
  below it the wall is vertical (a flat or ball end cannot reach below it from above);
- the plan-view areas of the grid cells must add up to the area enclosed by the projected
  boundary (shoelace formula): more means the footprint covers itself twice.

Points where ``s_u x s_v`` vanishes (a collapsed edge of a Bezier net) are skipped.
"""

from __future__ import annotations

import numpy as np

MIN_NZ = np.sin(np.radians(1.0))  # steepest accepted wall: 89 degrees
OVERLAP_TOLERANCE = 0.01  # relative excess of the cells' plan area over the footprint's


def height_field_problem(surface, n: int = 65) -> str | None:
    """Why ``surface`` is not a height field over its footprint, or ``None`` if it is."""
    t = np.linspace(0.0, 1.0, n)
    u, v = (a.ravel() for a in np.meshgrid(t, t, indexing="ij"))
    jet = surface.jet(u, v, order=1)
    cross = np.cross(jet.su, jet.sv)
    norm = np.linalg.norm(cross, axis=1)
    regular = norm > 1e-9 * max(float(np.median(norm)), 1e-300)
    if not regular.any():
        return "degenerate: its tangent plane is undefined everywhere"
    jz = cross[:, 2]
    signs = np.sign(jz[regular & (np.abs(jz) > MIN_NZ * norm)])
    if signs.size and signs.min() < 0 < signs.max():
        where = np.flatnonzero(regular & (np.sign(jz) != np.sign(np.median(signs))))[0]
        return f"folds over or overhangs (its normal turns downwards near u={u[where]:.2f}, v={v[where]:.2f})"
    steep = regular & (np.abs(jz) <= MIN_NZ * norm)
    if steep.any():
        i = np.flatnonzero(steep)[0]
        return f"has a vertical wall (slope above 89 degrees near u={u[i]:.2f}, v={v[i]:.2f})"
    xy = jet.p[:, :2].reshape(n, n, 2)
    cells = _cell_areas(xy)
    boundary = np.concatenate([xy[:, 0], xy[-1, 1:], xy[-2::-1, -1], xy[0, -2:0:-1]])
    x, y = boundary[:, 0], boundary[:, 1]
    footprint = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    if np.abs(cells).sum() > (1.0 + OVERLAP_TOLERANCE) * footprint:
        return "overlaps itself in plan view (self-intersecting or wound more than once)"
    return None


def _cell_areas(xy: np.ndarray) -> np.ndarray:
    """Signed plan areas of the grid's quadrilateral cells (half the cross product of the diagonals)."""
    d1 = xy[1:, 1:] - xy[:-1, :-1]
    d2 = xy[:-1, 1:] - xy[1:, :-1]
    return 0.5 * (d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0])


def check_height_field(surface, key: str = "surface") -> None:
    """``ValueError('key: the surface ...')`` unless ``surface`` is machinable from above."""
    problem = height_field_problem(surface)
    if problem is not None:
        raise ValueError(f"{key}: the surface {problem}; the toolpath model needs a surface "
                         "that is a height field over its footprint")
