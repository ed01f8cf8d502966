"""Sizes of a machining job estimated from its settings, before anything is allocated.

Every array that the settings size (the stock's Z-map, the roughing layers, the tool's
footprint and the work of sliding it, the semi-finish and finish point grids) is counted
first; a job that cannot fit in ``max_bytes`` or exceeds a ceiling is refused with one
``ValueError`` naming the setting and the number. The estimates count the main arrays and
their working copies: the right order of magnitude, not the exact peak.
"""

from __future__ import annotations


import numpy as np

from .operations import _span

MAX_POINTS = 20_000_000  # points of one operation's toolpath (an NC program of that many blocks)
MAX_LAYERS = 100_000
MAX_FILTER_WORK = 2e10  # cell x footprint-cell visits of the tool's maximum filter (minutes of CPU)
ZMAP_BYTES = 8 * 12  # per stock cell: heights, floor, fields and their copies (float64)
POINT_BYTES = 8 * 3 * 8  # per toolpath point: tips, axes, offsets, normals and copies


def _gib(n: float) -> str:
    return f"{n / 2**30:.3g} GiB"


def check_sizes(cfg: dict, surface, max_bytes: float | None) -> None:
    """Refuse settings whose arrays or work cannot fit (module docstring)."""
    t = np.linspace(0, 1, 41)
    u, v = np.meshgrid(t, t)
    p = surface.points(u.ravel(), v.ravel())
    (x0, y0, z0), (x1, y1, z1) = p.min(axis=0), p.max(axis=0)
    st, ro, al = cfg["stock"], cfg["roughing"], cfg["allowances"]
    cell = float(st["cell"])
    # Python float counts: a cell of 1e-300 mm gives counts no int-to-float conversion takes;
    # a float product past 1.8e308 is inf, which the ceilings refuse
    cells = (float(np.ceil(float(x1 - x0) / cell)) + 1.0) * (float(np.ceil(float(y1 - y0) / cell)) + 1.0)
    _fits(cells * ZMAP_BYTES, max_bytes, f"stock.cell: a {cell:g} mm Z-map over {x1 - x0:.1f} x {y1 - y0:.1f} mm "
                                         f"({cells:.3g} cells)")
    z_top = float(st["top"]) if st.get("top") is not None else z1 + float(st["top_offset"])
    depth = float(ro["max_depth"])
    if depth > 0:
        layers = (z_top - z0) / depth
        if layers > MAX_LAYERS:
            raise ValueError(f"roughing.max_depth: {depth:g} mm cuts the {z_top - z0:.1f} mm of stock into "
                             f"{layers:.3g} layers (at most {MAX_LAYERS:,})")
        per_layer = 8 if ro["method"].startswith("morphing") else 1
        _fits(layers * cells * per_layer, max_bytes, f"roughing.max_depth: {layers:.3g} layers of {cells:.3g} cells")
    reach = 0.5 * float(ro["tool"]["diameter"]) + float(al["semifinish"]) + float(al["finish"]) + cell
    side = 2.0 * float(np.floor(reach / cell)) + 1.0
    disk = side * side  # (a float ** 2 raises OverflowError where * gives inf)
    _fits(disk * 8 * 3, max_bytes, f"roughing.tool.diameter: a {ro['tool']['diameter']:g} mm tool's footprint "
                                   f"({disk:.3g} cells of {cell:g} mm)")
    if disk * cells > MAX_FILTER_WORK:
        raise ValueError(f"roughing.tool.diameter: a {ro['tool']['diameter']:g} mm tool over {cells:.3g} cells of "
                         f"{cell:g} mm is {disk * cells:.3g} cell visits (at most {MAX_FILTER_WORK:.3g}): "
                         "use a coarser stock.cell")
    ops = [("semifinish", cfg["semifinish"])]
    if cfg["finish"].get("source") != "plan":
        ops.append(("finish", cfg["finish"]))
    span_u, span_v = _span(surface, "u"), _span(surface, "v")
    for name, op in ops:
        points = (span_u / float(op["step"]) + 2) * (span_v / float(op["stepover"]) + 2)
        if points > MAX_POINTS:
            raise ValueError(f"{name}.step: {op['step']:g} mm steps at {op['stepover']:g} mm step-over make "
                             f"{points:.3g} points (at most {MAX_POINTS:,})")
        _fits(points * POINT_BYTES, max_bytes, f"{name}.step: {points:.3g} points")


def _fits(nbytes: float, max_bytes: float | None, what: str) -> None:
    if max_bytes is not None and nbytes > max_bytes:
        raise ValueError(f"{what} needs about {_gib(nbytes)} of memory; {_gib(max_bytes)} are available")
