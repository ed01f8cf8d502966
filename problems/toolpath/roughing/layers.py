"""Roughing layers over a block stock: Abbas' morphing layers and the z-level baseline.

Everything lives on one XY grid over the surface's footprint (cell centres ``xs``, ``ys``):

- ``height_field``: the surface as z(x, y), the highest surface sample in each cell (-inf
  where the surface has none). The samples span the whole parameter square: over a trimmed
  face's holes and notches (and a mesh's gaps) that is the face's continuation, the surface
  the semi-finish's ball also follows there (``operations.py`` says why the block is roughed
  to it); ``footprint_cells`` marks the cells on the part itself.
- ``floor_field``: F(x, y), the lowest height the bottom of a flat end mill of radius R may
  take with its axis at (x, y) and still stay ``allowance`` away from the surface: the
  surface heights dilated by a disk of radius R + allowance (+ half a cell diagonal, for the
  grid), plus the allowance. If every surface point within R + a of the axis lies at least a
  below the tool's bottom, every point of the tool (a flat-bottomed cylinder) is at least a
  from the surface, so a tool at or above F never cuts into the allowance.

Abbas' steps (Sec. "Intermediate Layers Generation"):

1. the surface data; 2. D_z = (Z_max + 5) - Z_min (the stock top, 5 mm above the surface by
default); 3. D_layers = D_z - (D_off1 + D_off2); 4. the maximum depth of cut D_cut;
5. N_layers = D_layers / D_cut, rounded up here so that no layer is deeper than D_cut;
6. the layers: layer k of N morphs the stock top into the floor,
   H_k(x, y) = z_top + (k / N) (F(x, y) - z_top), k = 1..N, only z changing (x, y stay).

Since F >= Z_min + a, a layer is at most (z_top - Z_min - a) / N = D_layers / N <= D_cut
below the previous one at any (x, y).

The z-level baseline cuts flat levels z_j = z_top - j (z_top - min F) / N_z, j = 1..N_z with
N_z from the same formula (equal max depth of cut), each only where F <= z_j.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage


@dataclass
class Grid:
    """Cell centres xs (nx,), ys (ny,) of square cells of side ``cell``; arrays are (ny, nx)."""

    xs: np.ndarray
    ys: np.ndarray
    cell: float

    @classmethod
    def over(cls, lo, hi, cell: float) -> "Grid":
        """The grid whose cells cover the rectangle lo = (x0, y0) .. hi = (x1, y1)."""
        nx = max(1, int(math.ceil((hi[0] - lo[0]) / cell - 1e-9)))
        ny = max(1, int(math.ceil((hi[1] - lo[1]) / cell - 1e-9)))
        return cls(lo[0] + cell * (np.arange(nx) + 0.5), lo[1] + cell * (np.arange(ny) + 0.5), cell)

    def index(self, x, y):
        """(row, col) of the cells holding points x, y (clipped to the grid)."""
        c = np.clip(np.floor((np.asarray(x) - self.xs[0]) / self.cell + 0.5), 0, len(self.xs) - 1).astype(int)
        r = np.clip(np.floor((np.asarray(y) - self.ys[0]) / self.cell + 0.5), 0, len(self.ys) - 1).astype(int)
        return r, c

    def disk(self, radius: float) -> np.ndarray:
        """Boolean footprint of the cells whose centres lie within ``radius`` of a cell's centre."""
        n = int(math.floor(radius / self.cell))
        i = np.arange(-n, n + 1) * self.cell
        return (i[None, :] ** 2 + i[:, None] ** 2) <= radius * radius + 1e-12


    def local_max(self, field: np.ndarray, row: int, col: int, radius: float) -> float:
        """Highest value of ``field`` (ny, nx) over the cells within ``radius`` of cell (row, col)."""
        n = int(math.floor(radius / self.cell))
        r0, c0 = max(row - n, 0), max(col - n, 0)
        win = field[r0:row + n + 1, c0:col + n + 1]
        d = self.disk(radius)[r0 - row + n:r0 - row + n + win.shape[0], c0 - col + n:c0 - col + n + win.shape[1]]
        return float(win[d].max())


def layer_count(z_top: float, z_min: float, allowance_semi: float, allowance_finish: float, d_cut: float) -> int:
    """Abbas steps 2, 3 and 5: N = ceil(D_layers / D_cut), D_layers = D_z - (D_off1 + D_off2),
    D_z = z_top - Z_min (z_top = Z_max + 5 by default)."""
    d_layers = (z_top - z_min) - (allowance_semi + allowance_finish)
    if d_cut <= 0:
        raise ValueError("max depth of cut must be > 0")
    return max(1, int(math.ceil(d_layers / d_cut - 1e-9)))


def height_field(surface, grid: Grid, samples: int | None = None) -> np.ndarray:
    """(ny, nx) highest surface z per cell from a dense (u, v) sampling (-inf: no sample)."""
    if samples is None:
        span = max(grid.xs[-1] - grid.xs[0], grid.ys[-1] - grid.ys[0]) + grid.cell
        samples = int(min(1500, max(50, 3 * span / grid.cell)))
    t = np.linspace(0.0, 1.0, samples)
    u, v = np.meshgrid(t, t, indexing="ij")
    p = surface.points(u.ravel(), v.ravel())
    r, c = grid.index(p[:, 0], p[:, 1])
    z = np.full((len(grid.ys), len(grid.xs)), -np.inf)
    np.maximum.at(z, (r, c), p[:, 2])
    return z


def footprint_cells(surface, grid: Grid) -> np.ndarray:
    """(ny, nx) the cells whose centre lies on the part: inside the surface's trimmed
    footprint in plan view (every cell for a surface over its whole parameter square)."""
    from ..geometry.crossings import inside_grid
    from ..geometry.footprint import footprint_of

    footprint = footprint_of(surface)
    if footprint.whole:
        return np.ones((len(grid.ys), len(grid.xs)), bool)
    return inside_grid(footprint.xy_loops(surface), grid.xs, grid.ys)


def floor_field(z: np.ndarray, grid: Grid, tool_radius: float, allowance: float) -> np.ndarray:
    """F (ny, nx): lowest allowed flat-end-mill bottom per axis position (module docstring).
    Cells whose disk holds no surface sample get the lowest surface height + allowance."""
    reach = tool_radius + allowance + grid.cell * math.sqrt(0.5)
    f = ndimage.maximum_filter(z, footprint=grid.disk(reach), mode="constant", cval=-np.inf)
    lowest = z[np.isfinite(z)].min()
    return np.where(np.isfinite(f), f, lowest) + allowance


def morph_layers(floor: np.ndarray, z_top: float, n_layers: int) -> np.ndarray:
    """Abbas step 6: (N, ny, nx) layers H_k = z_top + (k/N)(F - z_top), k = 1..N."""
    k = np.arange(1, n_layers + 1)[:, None, None] / n_layers
    return z_top + k * (floor[None] - z_top)


def z_levels(floor: np.ndarray, z_top: float, n_levels: int) -> np.ndarray:
    """(N,) flat levels from just below the stock top down to min F, equally spaced."""
    return z_top - np.arange(1, n_levels + 1) * (z_top - floor.min()) / n_levels
