"""What the cut left: scallop, gouge and uncut figures from the residual grid.

Every figure is over the cells on the part, weighted by the cell's surface area clipped
to the part (``DesignGrid.cell_area``, ``clip.py``: a cell straddling the footprint's edge
weighs only its inside part):

- material left (scallop): max(residual, 0), clipped at the ``allowance`` (the finishing
  stock: a cell no cutter pose reached keeps exactly that much); max, area-weighted mean
  and the 50th / 90th / 99th percentiles;
- gouge (cut below the design surface): max(-residual, 0); its maximum and the area (mm^2)
  where it is deeper than ``gouge_threshold`` (round-off of a cutter touching the surface
  exactly is not a gouge);
- uncut fraction: the share of the part's area that no pose brought within the allowance.

Per-zone figures use a label per cell (-1 off every zone). :func:`meets_h_c` is the verdict
a plan is judged by (p99 under h_c, max at most 1.1 h_c, nothing uncut, gouge within the
chord tolerance), read on a 0.05 mm grid; :func:`verdicts` sets it side by side on several
grids and flags a verdict that changes between the two finest.
"""

from __future__ import annotations

import numpy as np

from .design import DesignGrid

__all__ = ["residual_metrics", "zone_metrics", "KEYS", "meets_h_c", "verdicts", "VERDICT_GRID_MM",
           "VERDICT_GRIDS_MM"]

KEYS = ("scallop_max_mm", "scallop_mean_mm", "scallop_p50_mm", "scallop_p90_mm",
        "scallop_p99_mm", "gouge_max_mm", "gouge_area_mm2", "uncut_fraction", "area_mm2")


def _weighted_quantiles(values: np.ndarray, weights: np.ndarray, qs) -> list[float]:
    order = np.argsort(values)  # ties hold equal values: their order does not matter
    v, w = values[order], weights[order]
    cw = np.cumsum(w)
    return [float(v[min(np.searchsorted(cw, q * cw[-1]), len(v) - 1)]) for q in qs]


def _metrics(res: np.ndarray, area: np.ndarray, allowance: float, gouge_threshold: float) -> dict:
    if res.size == 0 or area.sum() <= 0:
        return {k: float("nan") for k in KEYS}
    left = np.clip(res, 0.0, allowance)
    gouge = np.maximum(-res, 0.0)
    uncut = ~(res < allowance)
    p50, p90, p99 = _weighted_quantiles(left, area, (0.5, 0.9, 0.99))
    total = float(area.sum())
    return {
        "scallop_max_mm": float(left.max()),
        "scallop_mean_mm": float((left * area).sum() / total),
        "scallop_p50_mm": p50, "scallop_p90_mm": p90, "scallop_p99_mm": p99,
        "gouge_max_mm": float(gouge.max()),
        "gouge_area_mm2": float(area[gouge > gouge_threshold].sum()),
        "uncut_fraction": float(area[uncut].sum() / total),
        "area_mm2": total,
    }


def residual_metrics(grid: DesignGrid, residual: np.ndarray, allowance: float = 0.5,
                     gouge_threshold: float = 1e-3, mask: np.ndarray | None = None) -> dict:
    """The figures of the module docstring over the part (or the cells of ``mask``)."""
    keep = grid.inside & (True if mask is None else mask)
    return _metrics(residual[keep], grid.cell_area()[keep], allowance, gouge_threshold)


def zone_metrics(grid: DesignGrid, residual: np.ndarray, labels: np.ndarray,
                 allowance: float = 0.5, gouge_threshold: float = 1e-3) -> list[dict]:
    """The same figures per zone: ``labels`` (ny, nx) zone of each cell (-1: none)."""
    out = []
    for z in range(int(labels.max()) + 1 if labels.size else 0):
        out.append({"zone": z, **residual_metrics(grid, residual, allowance, gouge_threshold,
                                                  mask=labels == z)})
    return out


def cell_labels(grid: DesignGrid, mesh_labels: np.ndarray) -> np.ndarray:
    """(ny, nx) zone of each cell from zone labels on an (n, m) parametric mesh."""
    n, m = mesh_labels.shape
    u = np.nan_to_num(grid.u, nan=-1.0)
    v = np.nan_to_num(grid.v, nan=-1.0)
    iu = np.clip((u * n).astype(int), 0, n - 1)
    iv = np.clip((v * m).astype(int), 0, m - 1)
    return np.where(grid.inside, mesh_labels[iu, iv], -1)


#: the grid (mm) a "meets h_c" verdict is read on, and the grids reproduction tables show
VERDICT_GRID_MM = 0.05
VERDICT_GRIDS_MM = (0.2, 0.1, 0.05)


def meets_h_c(metrics: dict, h_c: float, tolerance: float) -> tuple[bool, list[str]]:
    """Whether a simulated cut meets the scallop target h_c, and why not: its p99 under
    h_c, its max at most 1.1 h_c, nothing uncut, the gouge within the chord tolerance.
    ``metrics``: the figures of :func:`residual_metrics` (read it on a 0.05 mm grid,
    ``VERDICT_GRID_MM``, before calling a plan good)."""
    why = []
    if not metrics["scallop_p99_mm"] < h_c:
        why.append(f"p99 {metrics['scallop_p99_mm']:.3f} >= h_c {h_c:g}")
    if not metrics["scallop_max_mm"] <= 1.1 * h_c:
        why.append(f"max {metrics['scallop_max_mm']:.3f} > 1.1 h_c {1.1 * h_c:.3f}")
    if metrics["uncut_fraction"] > 0:
        why.append(f"uncut {100 * metrics['uncut_fraction']:.3f} % of the area")
    if not metrics["gouge_max_mm"] <= tolerance:
        why.append(f"gouge {metrics['gouge_max_mm']:.4f} > tolerance {tolerance:g}")
    return not why, why


def verdicts(by_grid: dict, h_c: float, tolerance: float) -> dict:
    """The verdict on each grid (``by_grid``: grid mm -> metrics) side by side: per grid
    (meets, reasons), ``final`` the verdict on the finest grid, ``flip`` True when the
    verdict on the finest grid differs from the next coarser one (a verdict the coarser
    grid would have got wrong)."""
    grids = sorted(by_grid, reverse=True)
    out = {g: meets_h_c(by_grid[g], h_c, tolerance) for g in grids}
    flip = len(grids) > 1 and out[grids[-1]][0] != out[grids[-2]][0]
    return {"by_grid": out, "final": out[grids[-1]][0], "flip": bool(flip)}
