"""The operation set for one surface: roughing from a block, semi-finish, finish (Abbas' stages).

- ``roughing``: Abbas' morphing layers (cut where material remains, ``remaining.py``, or over
  the whole block) or the z-level baselines (``layers.py``; zig-zag ``zigzag.py``, contour-
  parallel ``contour.py``) with a flat end mill, checked on a stock Z-map (``zmap.py``).

The block covers the surface's XY box, and on a trimmed face (a STEP face's hole or notch)
or a mesh with gaps that box holds cells off the part. There the roughing floor is the
face's continuation over its parameter square (plus the allowance, dilated by the tool like
everywhere), not the block's bottom and not the untouched stock top, because:

- the semi-finish (``ball_on_offset``) runs its ball over the whole parameter square, so
  over a hole it follows the same continuation: roughed to it, the ball meets only its
  allowance there, as everywhere; left at the stock top, it would plunge into full stock;
- what lies below a face outside its footprint is not known from the face: the rest of the
  solid (a blind pocket's floor, a neighbouring face of the same top) may be there, so
  cutting deeper (to the lowest point of the face, or the block's bottom) could cut the
  part. The hole and the notch are other features' operations (drilling, pocketing);
- the finish plan itself stays on the footprint (its sections stop at the trim).

The figures measured against the part (``left_min`` / ``left_max``: stock left above the
surface) are read on the footprint's cells only (``Stock.part``).
- ``ball_on_offset``: 3-axis ball-end zig-zag along iso-parametric curves (passes at constant
  v, points along u), the ball centre on the exact normal offset at R + allowance
  (``offset.py``): semi-finish with allowance D_off2, finish with 0.
- ``finish_from_plan``: the finishing toolpath of one decision set of the evoplan toolpath
  problem (``ToolpathProblem.cl_path``: the CL points, axes, passes and sections of the one
  engine's plan, 5-axis or 3-axis, zoned or not: the path the run's ``toolpath.apt`` holds).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..export.toolpath import Tool, Toolpath
from .layers import (Grid, floor_field, footprint_cells, height_field, layer_count, morph_layers,
                     z_levels)
from .offset import normal_offset
from .zigzag import morph_path, zlevel_path
from .zmap import StockZMap


@dataclass
class Stock:
    """Block over the surface's XY box, top at ``z_top``; the surface's height field on ``grid``
    (over the whole parameter square) and ``part``, its cells on the part's footprint (None:
    every cell)."""

    grid: Grid
    z_surface: np.ndarray
    z_top: float
    part: np.ndarray | None = None

    @property
    def z_min(self) -> float:
        return float(self.z_surface[np.isfinite(self.z_surface)].min())

    @property
    def z_max(self) -> float:
        return float(self.z_surface.max())


def surface_z_range(surface, n: int = 129) -> tuple[float, float]:
    """(z_min, z_max) of the surface itself: the extremes of an n x n parametric sample, each
    polished by a bounded quasi-Newton search over (u, v), so they are the surface's, not a
    Z-map's cell centres (which read the lowest point up to a cell's slope too high)."""
    from scipy.optimize import minimize

    t = np.linspace(0.0, 1.0, n)
    u, v = (a.ravel() for a in np.meshgrid(t, t))
    z = surface.points(u, v)[:, 2]
    out = []
    for sign in (1.0, -1.0):
        i = int(np.argmin(sign * z))

        def height(x, sign=sign):
            return sign * float(surface.points(np.array([x[0]]), np.array([x[1]]))[0, 2])

        best = minimize(height, [u[i], v[i]], method="L-BFGS-B", bounds=[(0, 1), (0, 1)])
        out.append(sign * min(best.fun, sign * z[i]))
    return out[0], out[1]


def block_stock(surface, cell: float, top: float | None = None, top_offset: float = 5.0) -> Stock:
    """The block: XY box of the surface (sampled), top at ``top`` or z_max + ``top_offset``.
    ValueError ``stock.top: ...`` if the top is below the surface."""
    t = np.linspace(0, 1, 201)
    u, v = np.meshgrid(t, t)
    p = surface.points(u.ravel(), v.ravel())
    grid = Grid.over(p[:, :2].min(axis=0), p[:, :2].max(axis=0), cell)
    z = height_field(surface, grid)
    z_max = float(z.max())
    if top is not None and top < z_max:
        raise ValueError(f"stock.top: {top:g} is below the surface (its highest point is z = {z_max:.3f})")
    return Stock(grid, z, z_max + top_offset if top is None else float(top),
                 footprint_cells(surface, grid))


def roughing(stock: Stock, method: str, tool: Tool, *, d_cut: float, stepover: float, allowance_semi: float,
             allowance_finish: float, feed: float, plunge_feed: float, tolerance: float = 0.01,
             clearance: float = 10.0, rapid: float = 10000.0):
    """(toolpath, stats, layers): ``method`` 'morphing' (where material remains above each
    layer, ``remaining.py``), 'morphing_full' (every layer over the block), 'zlevel' or
    'contour'; stats from the Z-map. ``rapid`` (mm/min) weighs a retract against staying down.
    ``layers`` (N, ny, nx) morphing layers or (N,) z levels, for the figure."""
    d_z = stock.z_top - stock.z_min
    if not 0 < d_cut <= d_z:
        raise ValueError(f"roughing.max_depth: {d_cut:g} must be > 0 and at most the stock depth D_z = {d_z:.3f} mm")
    a = allowance_semi + allowance_finish
    n = layer_count(stock.z_top, stock.z_min, allowance_semi, allowance_finish, d_cut)
    floor = floor_field(stock.z_surface, stock.grid, 0.5 * tool.diameter, a)
    kw = dict(z_top=stock.z_top, safe_z=stock.z_top + clearance, feed=feed, plunge_feed=plunge_feed,
              tolerance=tolerance, comments=[f"{method} roughing, {n} layers, max depth {d_cut:g} mm"])
    if method == "morphing":  # cut only where the stock Z-map has material above the layer
        from .remaining import morph_remaining_path

        layers = morph_layers(floor, stock.z_top, n)
        tp = morph_remaining_path(stock.grid, layers, tool, stepover, rapid=rapid, **kw)
    elif method == "morphing_full":  # every layer over the whole block, as Abbas draws them
        layers = morph_layers(floor, stock.z_top, n)
        tp = morph_path(stock.grid, layers, tool, stepover, **kw)
    elif method == "zlevel":
        layers = z_levels(floor, stock.z_top, n)
        tp = zlevel_path(stock.grid, floor, layers, tool, stepover, d_cut=d_cut, **kw)
    elif method == "contour":
        from .contour import contour_path

        layers = z_levels(floor, stock.z_top, n)
        tp = contour_path(stock.grid, floor, layers, tool, stepover, **kw)
    else:
        raise ValueError(f"roughing.method: unknown method {method!r} (known: morphing, morphing_full, zlevel, contour)")
    zmap = StockZMap(stock.grid, stock.z_top)
    stats = zmap.cut(tp)
    left_min, left_max = zmap.clearance_over(stock.z_surface, stock.part)  # on the part only
    stats.update(method=method, n_layers=n, d_z=d_z, d_layers=d_z - a, d_cut=d_cut, z_top=stock.z_top,
                 z_min=stock.z_min, allowance=a, left_min=left_min, left_max=left_max)
    return tp, stats, (floor, layers)


def _span(surface, along: str, samples: int = 101) -> float:
    """Length of the middle iso-curve along u ('u') or v ('v')."""
    t = np.linspace(0, 1, samples)
    u, v = (t, np.full_like(t, 0.5)) if along == "u" else (np.full_like(t, 0.5), t)
    return float(np.linalg.norm(np.diff(surface.points(u, v), axis=0), axis=1).sum())


def ball_on_offset(surface, tool: Tool, *, allowance: float, stepover: float, step: float, feed: float,
                   plunge_feed: float, name: str, clearance: float = 10.0) -> tuple[Toolpath, int]:
    """(toolpath, folded points): 3-axis ball-end zig-zag on the normal offset at R + allowance."""
    r = 0.5 * tool.diameter
    nv = int(math.ceil(_span(surface, "v") / stepover - 1e-9)) + 1
    nu = int(math.ceil(_span(surface, "u") / step - 1e-9)) + 1
    u, v = np.linspace(0, 1, nu), np.linspace(0, 1, nv)
    uu = np.concatenate([u if j % 2 == 0 else u[::-1] for j in range(nv)])
    vv = np.repeat(v, nu)
    off = normal_offset(surface, uu, vv, r + allowance)
    tip = off.points - [0.0, 0.0, r]
    axis = np.tile([0.0, 0.0, 1.0], (len(tip), 1))
    tp = Toolpath.from_passes(name, tool, tip, axis, np.repeat(np.arange(nv), nu), feed=feed,
                              plunge_feed=plunge_feed, clearance=clearance,
                              comments=[f"ball centre on the normal offset at R + {allowance:g} mm"])
    return tp, int(off.folded.sum())


def finish_from_plan(problem, variables: dict, number: int, spindle_rpm: float, *,
                     plunge_feed: float | None = None, clearance: float = 10.0) -> Toolpath:
    """The finishing path of one decision set ``variables`` (by name, the tool by its id) of
    ``problem`` (a ``ToolpathProblem``) as a Toolpath. A plan whose passes are each one
    section (a single zone) links them by cutting moves; a plan cut in separate sections
    (zones, stretches of a plane) retracts between them."""
    path, _ = problem.cl_path(variables)
    db = problem.tool_db
    tool_id = variables["tool"] if "tool" in variables else problem.fixed["tool"]
    t = db.tools[db.index_of(tool_id)]
    tool = Tool(number, t.cutter, spindle_rpm)
    decisions = ", ".join(f"{k} {float(v):g}" for k, v in {**problem.fixed, **variables}.items()
                          if k != "tool")
    text = f"evoplan plan: tool {t.id} ({t.label()}), {decisions}"
    one_per_pass = len(np.unique(path.section)) == len(np.unique(path.pass_index))
    if one_per_pass and np.all(path.zone == path.zone[0]):
        return Toolpath.from_passes("finish", tool, path.tip, path.axis, path.pass_index,
                                    feed=path.feed_rate, plunge_feed=plunge_feed,
                                    clearance=clearance, comments=[text])
    return Toolpath.from_sections("finish", tool, path.tip, path.axis, path.section,
                                  feed=path.feed_rate, plunge_feed=plunge_feed,
                                  clearance=clearance, comments=[text])
