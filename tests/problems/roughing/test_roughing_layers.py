"""Roughing layers (Abbas steps 1-6) and their zig-zag paths, checked on a stock Z-map."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.geometry.bezier import BezierSurface
from evoplan.problems.toolpath.export.toolpath import Tool
from evoplan.problems.toolpath.roughing.layers import (
    Grid, floor_field, height_field, layer_count, morph_layers, z_levels,
)
from evoplan.problems.toolpath.roughing.zigzag import morph_path, zlevel_path
from evoplan.problems.toolpath.roughing.zmap import StockZMap

A_SEMI, A_FIN, D_CUT, R = 0.5, 0.3, 3.0, 5.0


@pytest.fixture(scope="module")
def case():
    xs, ys = np.linspace(0, 60, 4), np.linspace(0, 50, 4)
    z = np.array([[0, 8, 4, 0], [8, 24, 20, 4], [4, 20, 16, 0], [0, 4, 0, -4]], float)
    net = np.concatenate([np.stack(np.meshgrid(xs, ys, indexing="ij"), -1), z[..., None]], -1)
    grid = Grid.over((0, 0), (60, 50), 0.5)
    zs = height_field(BezierSurface(net), grid)
    floor = floor_field(zs, grid, R, A_SEMI + A_FIN)
    z_top = zs.max() + 5
    n = layer_count(z_top, zs.min(initial=np.inf, where=np.isfinite(zs)), A_SEMI, A_FIN, D_CUT)
    return grid, zs, floor, z_top, n


def test_layer_count_is_abbas_steps_two_to_five():
    # D_z = (Z_max + 5) - Z_min = 35, D_layers = 35 - (1.5 + 0.5) = 33, N = ceil(33 / 4) = 9
    assert layer_count(30 + 5, 0, 1.5, 0.5, 4.0) == 9
    assert layer_count(35, 0, 1.5, 0.5, 3.3) == 10          # 33 / 3.3 = 10 exactly: no extra layer
    assert layer_count(35, 0, 1.5, 0.5, 100.0) == 1
    with pytest.raises(ValueError):
        layer_count(35, 0, 1.5, 0.5, 0.0)


def test_layers_stay_between_stock_and_allowance(case):
    grid, zs, floor, z_top, n = case
    layers = morph_layers(floor, z_top, n)
    assert layers.shape == (n,) + zs.shape
    assert np.all(layers <= z_top) and np.all(layers >= floor - 1e-12)
    np.testing.assert_allclose(layers[-1], floor)
    inside = np.isfinite(zs)
    assert np.all(floor[inside] >= zs[inside] + A_SEMI + A_FIN)      # never below the allowance surface
    steps = -np.diff(np.concatenate([np.full((1,) + zs.shape, z_top), layers]), axis=0)
    assert steps.max() <= D_CUT and steps.min() >= 0
    levels = z_levels(floor, z_top, n)
    assert np.all(np.diff(np.r_[z_top, levels]) < 0) and levels[-1] == pytest.approx(floor.min())


@pytest.mark.parametrize("method", ["morphing", "zlevel"])
def test_zmap_depth_of_cut_and_allowance(case, method):
    grid, zs, floor, z_top, n = case
    tool = Tool(1, make_cutter(2 * R, 0.0), 6000)
    kw = dict(z_top=z_top, safe_z=z_top + 10, feed=800, plunge_feed=300, tolerance=0.01)
    if method == "morphing":
        tp = morph_path(grid, morph_layers(floor, z_top, n), tool, 0.6 * 2 * R, **kw)
    else:
        tp = zlevel_path(grid, floor, z_levels(floor, z_top, n), tool, 0.6 * 2 * R, **kw)
    zmap = StockZMap(grid, z_top)
    stats = zmap.cut(tp)
    assert 0 < stats["max_depth"] <= D_CUT
    assert stats["rapid_volume"] == 0.0                               # no rapid into the stock
    assert len(stats["layers"]) == n and all(s["removed_mm3"] > 0 for s in stats["layers"])
    # the volume removed is the volume between the block top and what is left
    np.testing.assert_allclose(stats["removed_mm3"], (z_top - zmap.h).sum() * grid.cell ** 2, rtol=1e-9)
    left_min, _ = zmap.clearance_over(zs)
    assert left_min >= A_SEMI + A_FIN - 0.01                          # path tolerance only
    assert 0 <= stats["air_length"] <= tp.lengths()["cutting"] + tp.lengths()["plunge"]


def test_air_cutting_is_measured(case):
    grid, zs, floor, z_top, n = case
    tool = Tool(1, make_cutter(2 * R, 0.0), 6000)
    layers = morph_layers(floor, z_top, n)
    kw = dict(z_top=z_top, safe_z=z_top + 10, feed=800, plunge_feed=300)
    once = morph_path(grid, layers, tool, 6.0, **kw)
    twice = morph_path(grid, np.concatenate([layers, layers]), tool, 6.0, **kw)   # second run cuts air
    a, b = StockZMap(grid, z_top).cut(once), StockZMap(grid, z_top).cut(twice)
    assert b["removed_mm3"] == pytest.approx(a["removed_mm3"])
    repeat = sum(s["cutting_length"] for s in b["layers"][n:])
    assert b["air_length"] - a["air_length"] == pytest.approx(repeat, rel=1e-6)


def test_zlevel_links_never_cut_deeper_than_the_depth_of_cut():
    # concave-convex net: a diagonal link between raster lines crosses material the level
    # above never reached; unchecked it cuts deeper than D_cut, probed it retracts instead
    xs, ys = [0, 33, 67, 100], [0, 27, 53, 80]
    z = [[40, 20, 0, 20], [20, -30, 70, 0], [0, 70, -30, 20], [20, 0, 20, 40]]
    net = np.array([[[xs[i], ys[j], z[i][j]] for j in range(4)] for i in range(4)], float)
    grid = Grid.over((0, 0), (100, 80), 0.5)
    zs = height_field(BezierSurface(net), grid)
    floor = floor_field(zs, grid, 6.0, 0.8)
    z_top, d_cut = zs.max() + 5, 2.0
    levels = z_levels(floor, z_top, layer_count(z_top, zs.min(initial=np.inf, where=np.isfinite(zs)), 0.5, 0.3, d_cut))
    kw = dict(z_top=z_top, safe_z=z_top + 10, feed=800, plunge_feed=300)
    tool = Tool(1, make_cutter(12.0, 0.0), 6000)
    unchecked = StockZMap(grid, z_top).cut(zlevel_path(grid, floor, levels, tool, 7.2, **kw))
    checked = StockZMap(grid, z_top).cut(zlevel_path(grid, floor, levels, tool, 7.2, d_cut=d_cut, **kw))
    assert unchecked["max_depth"] > d_cut >= checked["max_depth"]
    assert checked["removed_mm3"] == pytest.approx(unchecked["removed_mm3"], rel=0.02)


def test_the_surface_z_range_is_the_surfaces_not_a_zmaps():
    """summary.json's z_min / z_max: the surface's own extremes (a dense sample cannot beat them),
    where the Z-map's cell centres read the lowest point too high."""
    from evoplan.problems.toolpath.geometry.surface import fountas_surface
    from evoplan.problems.toolpath.roughing.operations import block_stock, surface_z_range

    surface = fountas_surface()
    z_min, z_max = surface_z_range(surface)
    t = np.linspace(0, 1, 1501)
    u, v = (a.ravel() for a in np.meshgrid(t, t))
    z = surface.points(u, v)[:, 2]
    assert z.min() - 1e-4 <= z_min <= z.min() + 1e-9
    assert z.max() - 1e-9 <= z_max <= z.max() + 1e-4
    assert block_stock(surface, 1.0).z_min > z_min + 1e-3  # what the summary used to report


def test_morphing_cuts_only_where_material_remains(case):
    from evoplan.problems.toolpath.roughing.remaining import morph_remaining_path

    grid, zs, floor, z_top, n = case
    tool = Tool(1, make_cutter(2 * R, 0.0), 6000)
    layers = morph_layers(floor, z_top, n)
    kw = dict(z_top=z_top, safe_z=z_top + 10, feed=800, plunge_feed=300, tolerance=0.01)
    full = StockZMap(grid, z_top).cut(morph_path(grid, layers, tool, 6.0, **kw))
    tp = morph_remaining_path(grid, np.concatenate([layers, layers]), tool, 6.0, **kw)
    zmap = StockZMap(grid, z_top)
    aware = zmap.cut(tp)
    # the repeated layers find no material: nothing of them is cut, not even in air
    assert [s["section"] for s in aware["layers"]] == list(range(n))
    assert aware["removed_mm3"] == pytest.approx(full["removed_mm3"], rel=1e-3)
    assert aware["max_depth"] <= D_CUT and aware["rapid_volume"] == 0.0
    assert zmap.clearance_over(zs)[0] >= A_SEMI + A_FIN - 0.01
    # no slower than the whole-block zig-zag of the layers once (air is crossed only where
    # staying down is quicker than a retract, a rapid and a plunge)
    once = morph_path(grid, layers, tool, 6.0, **kw)
    assert tp.time_minutes(10000.0) <= once.time_minutes(10000.0)
