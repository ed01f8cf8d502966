"""Contour-parallel z-level roughing: the smooth slice lies inside the cells the tool may
reach, every offset contour lies inside the slice, the offsets are step-over apart."""

import numpy as np
from shapely.geometry import LineString

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.roughing.contour import cell_region, offset_rings, slice_region
from evoplan.problems.toolpath.roughing.layers import Grid


def test_offsets_lie_inside_the_slice_a_stepover_apart():
    xs, ys = np.arange(0, 60.01, 0.5), np.arange(0, 40.01, 0.5)
    grid = Grid(xs, ys, 0.5)
    X, Y = np.meshgrid(xs, ys)
    floor = np.where(np.hypot(X - 35, Y - 20) < 8, 10.0, 0.0)   # an island (the part) in the middle
    region = slice_region(grid, floor, 5.0)
    cells = cell_region(grid, floor, 5.0)
    assert cells.area == (len(xs) * len(ys) - (floor > 5).sum()) * 0.25
    # the smooth slice: inside the cells, at most a cell and a half (diagonal) in from them
    assert region.difference(cells).area < 1e-9
    assert cells.buffer(-1.5 * 0.5 * np.sqrt(2)).difference(region).area < 1e-9
    step = 3.0
    rings = offset_rings(region, step)
    assert len(rings) >= 4
    grown = region.buffer(1e-6)
    for k, level in enumerate(rings):
        for ring in level:
            assert grown.contains(LineString(ring))                 # inside the slice
            if k and k < len(rings) - 1:
                # every vertex of offset k is k step-overs from the slice's boundary (mitred corners: at least)
                line = LineString(ring)
                d = np.array([region.boundary.distance(line.interpolate(t, normalized=True))
                              for t in np.linspace(0, 1, 60, endpoint=False)])
                # round joins: k step-overs from the boundary (arcs as chords of 1/64 turn: 0.5 % in)
                assert k * step * (1 - 0.005) <= d.min() and d.max() <= k * step + 1e-6
    # the last (half-step) ring is what is left past the last full step
    assert len(rings[-1]) >= 1


def test_contour_roughing_leaves_the_allowance_and_cuts_at_each_level(tmp_path):
    from evoplan.problems.toolpath.geometry.spec import parse_surface
    from evoplan.problems.toolpath.export.toolpath import Tool
    from evoplan.problems.toolpath.roughing.operations import block_stock, roughing

    surface = parse_surface({"type": "bezier", "poles": [[[0, 0, 0], [0, 15, 4], [0, 30, 0]],
                                                         [[20, 0, 4], [20, 15, 14], [20, 30, 4]],
                                                         [[40, 0, 0], [40, 15, 4], [40, 30, 0]]]}, "surface")
    stock = block_stock(surface, 1.0)
    tp, stats, (floor, levels) = roughing(stock, "contour", Tool(1, make_cutter(8, 0), 6000), d_cut=3.0, stepover=4.8,
                                          allowance_semi=0.5, allowance_finish=0.3, feed=800, plunge_feed=250)
    assert stats["left_min"] >= 0.8 - 0.011 and stats["rapid_volume"] == 0
    cut_z = np.unique(np.round(tp.tip[~tp.rapid & ~tp.plunge, 2], 6))
    np.testing.assert_allclose(np.sort(cut_z), np.sort(levels), atol=1e-6)


def _turns(ring):
    """Turning angles (deg) between consecutive segments of a closed ring."""
    d = np.diff(ring, axis=0)
    d = d[np.hypot(*d.T) > 1e-9]
    a = np.arctan2(d[:, 1], d[:, 0])
    return np.degrees(np.abs((np.diff(np.r_[a, a[:1]]) + np.pi) % (2 * np.pi) - np.pi))


def test_the_slice_is_smooth_not_a_staircase_and_keeps_small_pockets():
    # a cone-shaped part: F = 12 - |p - c|; the level z = 6 leaves a round hole of radius 6
    xs, ys = np.arange(0, 40.01, 0.5), np.arange(0, 30.01, 0.5)
    grid = Grid(xs, ys, 0.5)
    X, Y = np.meshgrid(xs, ys)
    floor = 12.0 - np.hypot(X - 20.2, Y - 14.9)
    region, cells = slice_region(grid, floor, 6.0), cell_region(grid, floor, 6.0)
    assert region.difference(cells).area < 1e-9
    hole = np.asarray(region.interiors[0].coords)
    r = np.hypot(hole[:, 0] - 20.2, hole[:, 1] - 14.9)
    # the raised floor moves the boundary out by at most a cell diagonal: r in [6, 6 + 0.71]
    assert r.min() >= 6.0 - 1e-9 and r.max() <= 6.0 + 0.5 * np.sqrt(2) + 1e-9
    assert _turns(hole).max() < 30.0  # smooth: the cells' staircase turns by 90 degrees
    assert _turns(np.asarray(cells.interiors[0].coords)).max() == 90.0
    # a pocket of three cells only (the deepest level) is kept, as its cells
    pit = np.full((len(ys), len(xs)), 10.0)
    pit[10, 20:23] = 2.0
    small = slice_region(grid, pit, 2.0)
    assert small.area == 3 * 0.25 and small.equals(cell_region(grid, pit, 2.0))
