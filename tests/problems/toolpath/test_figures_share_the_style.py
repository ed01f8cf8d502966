"""The zone map (plan/zoning/figures.py) and the simulated cut's figures (simulation/figures.py)
are drawn in the shared style: evoplan.figure_style's resolution, palette and PNG output."""

from __future__ import annotations

import io

import numpy as np
import pytest
from matplotlib.colors import to_hex, to_rgba
from PIL import Image

from evoplan import figure_style
from evoplan.figure_style import DPI, PALETTE, zone_colors


def saved_dpi(data: bytes) -> float:
    with Image.open(io.BytesIO(data)) as im:
        assert im.format == "PNG"
        return im.info["dpi"][0]


@pytest.fixture(scope="module")
def grid():
    from evoplan.problems.toolpath.simulation.design import DesignGrid

    ny, nx = 30, 40
    normal = np.zeros((ny, nx, 3))
    normal[..., 2] = 1.0
    inside = np.ones((ny, nx), bool)
    inside[:, :3] = False
    residual = np.linspace(-0.02, 0.05, ny * nx).reshape(ny, nx)
    residual[5:8, 10:14] = 1.0                                   # uncut: above the allowance
    return DesignGrid(0.0, 0.0, 0.5, np.zeros((ny, nx)), normal, inside), residual


def test_the_deviation_figures_take_the_style(grid, monkeypatch):
    from evoplan.problems.toolpath.simulation.figures import (deviation_hist_figure, deviation_hist_png,
                                                              deviation_map_figure, deviation_map_png)

    g, residual = grid
    labels = (np.arange(40)[None, :] >= 20).astype(int).repeat(30, axis=0)
    kw = dict(tolerance=0.01, allowance=0.5)
    fig = deviation_map_figure(g, residual, labels=labels, **kw)
    fig.canvas.draw()
    assert fig.dpi == DPI and not any(line.get_visible() for line in fig.axes[0].xaxis.get_gridlines())
    assert "(mm)" in fig.axes[0].get_xlabel() and "(mm)" in fig.axes[0].get_ylabel()
    hist = deviation_hist_figure(g, residual, **kw)
    (ax,) = hist.axes
    assert hist.dpi == DPI and "(mm)" in ax.get_xlabel() and "(%)" in ax.get_ylabel()
    assert to_hex(ax.patches[0].get_facecolor()) == PALETTE[4].lower()
    assert {to_hex(line.get_color()) for line in ax.lines if line.get_linestyle() == "--"} == {PALETTE[5].lower()}
    for data in (deviation_map_png(g, residual, labels=labels, **kw), deviation_hist_png(g, residual, **kw)):
        assert saved_dpi(data) == pytest.approx(DPI, abs=0.05)          # was 130 before the shared style
    # the PNGs come from figure_style.png: the style's resolution follows it
    monkeypatch.setattr(figure_style, "DPI", 72)
    assert saved_dpi(deviation_hist_png(g, residual, **kw)) == pytest.approx(72, abs=0.05)


def test_the_zone_map_takes_the_style():
    from evoplan.problems.toolpath import choi_surface
    from evoplan.problems.toolpath.plan.zoning.figures import zone_map_figure, zone_map_png
    from evoplan.problems.toolpath.plan.zoning.plan import plan_zones
    from evoplan.problems.toolpath.plan.zoning.samples import sample_surface
    from evoplan.problems.toolpath.plan.zoning.stepover import ScallopTarget

    surface = choi_surface()
    samples = sample_surface(surface, spacing=1.0)
    plan = plan_zones(surface, ScallopTarget.build(3.175, 1.0, 0.254), "kmeans", mesh=(20, 20),
                      samples=samples, scan=4, K=3)
    zones = len(plan.zones)
    assert zones >= 2
    fig = zone_map_figure(surface, plan, samples)
    (ax,) = fig.axes
    passes = [tuple(c.get_colors()[0]) for c in ax.collections[2:]]     # mesh, borders, then each zone's passes
    assert passes == [to_rgba(c) for c in PALETTE[:zones]] == zone_colors(zones)
    assert fig.dpi == DPI and ax.get_xlabel() == "X (mm)" and ax.get_ylabel() == "Y (mm)"
    assert saved_dpi(zone_map_png(surface, plan, samples)) == pytest.approx(DPI, abs=0.05)


def test_zone_colours_beyond_the_palette_stay_distinct():
    assert zone_colors(7) == [to_rgba(c) for c in PALETTE[:7]]                  # no black fill
    many = zone_colors(12)
    assert len(set(many)) == 12
