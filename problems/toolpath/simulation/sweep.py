"""Sweep a toolpath over the design grid: CL path in, residual per cell out.

Prepares what the kernels visit. By moves (the default, ``moves.py``): every feed move
(consecutive CL points of one section) and every section of one point, each with how far
from its tip's segment (in XY) it can cut: ``Cutter.reach`` (the radius, plus the lean of a
tilted axis over the height of the cutting end), plus two cells. By stamps (the reference, ``stamp.py``): poses at most
``pose_step`` mm of tip travel apart along the feed moves, each with its path position, the
distance to its neighbours (the refinement's bracket), its section and the same reach.
Rapid moves between sections do not cut.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..clpath import CLPath
from .design import DesignGrid


def _drop_stale_numba_caches() -> None:
    """numba's on-disk cache of a function checks only its own file, not the kernels it
    calls from the others (kernel.py <- convex.py <- moves.py, kernel.py <- stamp.py): drop
    the cache entries older than any of those files, so an edited kernel is compiled again."""
    here = Path(__file__).parent
    newest = max((here / f"{m}.py").stat().st_mtime for m in ("kernel", "convex", "moves", "stamp"))
    for index in (here / "__pycache__").glob("*.nbi"):
        try:
            if index.stat().st_mtime < newest:
                index.unlink()
        except OSError:
            pass


_drop_stale_numba_caches()

from .kernel import _GOLD  # noqa: E402
from .moves import sweep_moves, tiles  # noqa: E402
from .stamp import sweep as sweep_stamps  # noqa: E402

__all__ = ["Residual", "sweep_path", "poses", "moves"]



@dataclass(frozen=True)
class Residual:
    """``values`` (ny, nx): entry parameter along each cell's ray (mm; > 0 material left,
    < 0 gouge, inf: no pose reached the cell, nan: off the part); ``vertical``: rays along
    z, else along the design-surface normal; ``poses`` the moves (or stamped poses) swept;
    ``work`` the kernel's counts of a sweep by moves (entries at CL points, moves searched,
    entries in the searches, golden-section entries), for the benchmark."""

    values: np.ndarray
    vertical: bool
    seconds: float
    poses: int = 0
    work: dict | None = None


def _sections(section: np.ndarray):
    m = len(section)
    start = np.r_[True, section[1:] != section[:-1]]
    first = np.flatnonzero(start)
    last = np.r_[first[1:] - 1, m - 1]
    owner = np.cumsum(start) - 1
    return first[owner], last[owner]


def poses(path: CLPath, pose_step: float):
    """(s, ds, lo, hi) of the stamped poses: path position, bracket half-width, section."""
    lo, hi = _sections(path.section)
    seg = np.linalg.norm(np.diff(path.tip, axis=0), axis=1)
    feed = path.feed_moves
    n = np.where(feed, np.maximum(np.ceil(seg / pose_step).astype(np.int64), 1), 0)
    move = np.repeat(np.arange(len(seg)), n)
    start = np.cumsum(n) - n
    k = np.arange(move.size) - start[move]
    s = move + k / n[move]
    ds = 1.0 / n[move]
    # the last point of each section of several points is a pose too
    idx = np.arange(len(path))
    ends = idx[(idx == hi) & (lo < hi)]
    s = np.r_[s, ends.astype(float)]
    ds = np.r_[ds, 1.0 / n[ends - 1]] if len(ends) else ds
    order = np.argsort(s, kind="stable")
    s, ds = s[order], ds[order]
    pi = np.minimum(np.floor(s).astype(np.int64), len(path) - 1)
    single = np.flatnonzero(lo == hi)  # a section of one point: a pose at the point
    s = np.r_[s, single.astype(float)]
    ds = np.r_[ds, np.zeros(len(single))]
    pi = np.r_[pi, single]
    return s, ds, lo[pi].astype(np.int64), hi[pi].astype(np.int64)


def moves(path: CLPath, h: float):
    """(i, j, reach) of the moves the sweep by moves visits: every feed move (CL point i ->
    j = i + 1) and every section of one point (i = j), with the XY radius around the tip's
    segment within which it can cut (as for the stamps)."""
    lo, hi = _sections(path.section)
    i = np.flatnonzero(path.feed_moves)
    single = np.flatnonzero(lo == hi)
    mi = np.r_[i, single].astype(np.int64)
    mj = np.r_[i + 1, single].astype(np.int64)
    order = np.argsort(mi, kind="stable")
    mi, mj = mi[order], mj[order]
    sin_tilt = np.sqrt(np.clip(1.0 - path.axis[:, 2] ** 2, 0.0, 1.0))
    reach = path.cutter.reach(np.maximum(sin_tilt[mi], sin_tilt[mj])) + 2.0 * h
    return mi, mj, reach


def _sweep_stamps(path, grid, res, vertical, pose_step, tol, n_slots):
    cutter, h = path.cutter, grid.h
    if pose_step is None:
        pose_step = 0.75 if cutter.corner_radius >= 0.5 else 0.25
    pose_step = float(pose_step)
    s, ds, lo, hi = poses(path, pose_step)
    pi = np.minimum(np.floor(s).astype(np.int64), len(path) - 1)
    sin_tilt = np.sqrt(np.clip(1.0 - path.axis[:, 2] ** 2, 0.0, 1.0))
    reach = cutter.reach(sin_tilt[pi]) + 2.0 * h
    n_golden = max(int(np.ceil(np.log(tol / (2.0 * pose_step)) / np.log(_GOLD))), 1)
    sweep_stamps(res, grid.x0, grid.y0, h, grid.z, grid.normal, grid.inside, bool(vertical),
                 path.tip, path.axis, s, ds, lo, hi, reach, cutter.kernel_params(), int(n_slots),
                 2, n_golden)
    return len(s), None


def tile_groups(ptr: np.ndarray, threads: int) -> list[np.ndarray]:
    """The tiles (with moves) cut into ``threads`` groups of about equal work: longest move
    lists first, each to the least loaded group (deterministic); tiles write disjoint cells."""
    counts = np.diff(ptr)
    groups: list[list[int]] = [[] for _ in range(threads)]
    load = [0] * threads
    for t in np.argsort(-counts, kind="stable")[: int(np.count_nonzero(counts))].tolist():
        g = load.index(min(load))
        groups[g].append(t)
        load[g] += int(counts[t])
    return [np.sort(np.asarray(g, dtype=np.int64)) for g in groups if g]


def _only(ptr: np.ndarray, tile_mv: np.ndarray, tiles_kept: np.ndarray):
    """(ptr, moves) listing only the moves of ``tiles_kept``; every other tile empty."""
    counts = np.diff(ptr)
    keep = np.zeros(counts.size, dtype=bool)
    keep[tiles_kept] = True
    sub = np.concatenate([[0], np.cumsum(np.where(keep, counts, 0))]).astype(ptr.dtype)
    return sub, tile_mv[np.repeat(keep, counts)]


def _sweep_moves(path, grid, res, vertical, tol, bend_tol, near_miss, tile_mm, threads=1):
    h, prm = grid.h, path.cutter.kernel_params()
    mi, mj, reach = moves(path, h)
    ny, nx = grid.shape
    ts = max(int(round(tile_mm / h)), 1)
    ptr, tile_mv = tiles(grid.x0, grid.y0, h, ny, nx, ts, path.tip, mi, mj, reach)
    seg = np.linalg.norm(path.tip[mj] - path.tip[mi], axis=1)
    longest = max(float(seg.max()) if len(seg) else 0.0, 4e-3)
    n_golden = max(int(np.ceil(np.log(4e-3 / longest) / np.log(_GOLD))), 1)
    def sweep(tile_ptr, moves_of_tiles):
        stats = np.zeros(4, np.int64)
        sweep_moves(res, grid.x0, grid.y0, h, grid.z, grid.normal, grid.inside, bool(vertical),
                    path.tip, path.axis, mi, mj, reach, ts, tile_ptr, moves_of_tiles, prm,
                    float(tol), float(bend_tol), float(near_miss), n_golden, stats)
        return stats

    groups = tile_groups(ptr, threads) if threads > 1 else []
    if len(groups) > 1:  # the kernel releases the GIL: one thread per group of tiles
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(len(groups)) as pool:
            stats = sum(pool.map(lambda g: sweep(*_only(ptr, tile_mv, g)), groups))
    else:
        stats = sweep(ptr, tile_mv)
    return len(mi), dict(zip(("point_entries", "moves_searched", "search_entries", "golden"),
                             stats.tolist()))


def sweep_path(path: CLPath, grid: DesignGrid, *, vertical: bool = False, method: str = "moves",
               tol: float | None = None, bend_tol: float = 1e-4, near_miss: float = 0.05, tile_mm: float = 1.0,
               pose_step: float | None = None, n_slots: int = 3, threads: int = 1) -> Residual:
    """The residual of every cell after the whole path has been cut (see the module doc).

    ``method="moves"`` (default, ``moves.py`` and ``convex.py``): every feed move is
    searched exactly for each cell it can reach, using the convexity of the entry along a
    move; ``tol`` (mm of entry, default 1e-5) is how far above the tangents' lower bound the
    search may stop, ``bend_tol`` the same for the allowance the turning axis needs;
    ``near_miss`` (mm): a move whose both ends miss the ray is searched when its closest
    pose misses by less; ``tile_mm``: the side of the tiles that list the moves; ``threads``:
    the tiles are shared among that many threads (each tile writes only its own cells, so the
    residual is the single-threaded one bit for bit). Measured
    on Fountas' part (0.2 mm grid, ``runs/bench/simulation_accuracy.py``) against the stamp
    sweep with poses 0.05 mm apart, 6 slots, refined to 2e-4 mm of travel: torus D16 r3
    (the VEGA set) within 5e-6 mm, ball D12 within 1e-5 mm, flat D8 within 1.6e-5 mm, on
    every cell (about the search's tolerance and the reference's own error). A ray that only
    grazes the rim far above the part (entries over ~1 mm) may stop at the search's 60
    entries a few um off.

    ``method="stamps"`` (``stamp.py``), the reference: poses ``pose_step`` mm of tip travel
    apart (default 0.75, 0.25 for a flat end), the ``n_slots`` deepest poses of different
    stretches per cell refined by golden-section search to ``tol`` mm of travel (default
    4e-3). Assumes nothing about the entry along a move, so with dense poses it checks the
    default; at its default spacing it can miss dips narrower than the stamps.
    """
    t0 = time.perf_counter()
    res = np.full(grid.shape, np.inf)
    if len(path) == 0:
        return Residual(res, vertical, 0.0)
    if method == "moves":
        n, work = _sweep_moves(path, grid, res, vertical, 1e-5 if tol is None else tol,
                               bend_tol, near_miss, tile_mm, int(threads))
    elif method == "stamps":
        n, work = _sweep_stamps(path, grid, res, vertical, pose_step,
                                4e-3 if tol is None else tol, n_slots)
    else:
        raise ValueError(f"sweep method: {method!r} is not 'moves' or 'stamps'")
    res[~grid.inside] = np.nan
    return Residual(res, bool(vertical), time.perf_counter() - t0, n, work)
