"""The toolpath figures read back from their Axes: the zone map holds every pass (run-on and
run-off past the part's right and top edges included), titles give each decision its unit and
say what the zoning made of its gene, the 3D view has one scale, the layers' legend sits off
the data, and no matplotlib warning leaks."""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pytest

from evoplan.problem_factory import make_problem
from evoplan.problems.toolpath.artifacts import _title, zone_map_figure, zoning_text
from evoplan.problems.toolpath.figures import cc_pattern_figure
from evoplan.problems.toolpath.roughing.figures import layers_figure


@pytest.fixture(scope="module")
def plan():
    problem = make_problem("toolpath", {
        "surface": "choi", "machine": "3axis", "tools": [{"id": 1, "type": "ball", "diameter": 6.35}],
        "spacing": "stepover", "feed_angle": 0, "ranges": {"stepover": [15, 60], "step": [0.5, 4]}})
    batch, genes = problem.plan(problem.check(np.array([[30.0, 2.0]])))
    return problem, batch, genes


def test_the_zone_map_holds_every_pass_past_the_part_edges(plan):
    problem, batch, genes = plan
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = zone_map_figure(problem.surface, batch, problem.labels(genes), "t")
    ax = fig.axes[0]
    secs = np.flatnonzero(batch.sec_ind == 0)
    xy = np.concatenate([batch.p[batch.sec_start[s]:batch.sec_start[s] + batch.sec_count[s], :2] for s in secs])
    part = problem.surface.points(np.array([0.0, 1.0, 0.0, 1.0]), np.array([0.0, 0.0, 1.0, 1.0]))
    # passes reach the part's right and top edges (and run on past the left one), where the
    # mesh's own limits would put them on the frame, half hidden
    assert xy[:, 0].max() >= part[:, 0].max() - 1e-9 and xy[:, 1].max() >= part[:, 1].max() - 1e-9
    assert xy[:, 0].min() < part[:, 0].min()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    gap = 0.01 * (x1 - x0)  # every pass at least 1 % of the width inside the frame
    assert x0 + gap < xy[:, 0].min() and xy[:, 0].max() < x1 - gap
    assert y0 + gap < xy[:, 1].min() and xy[:, 1].max() < y1 - gap
    plt.close(fig)


def test_titles_carry_units_and_say_what_the_zoning_made_of_its_gene(plan):
    problem, batch, genes = plan
    title = _title(problem, genes, batch)
    assert "step-over 30 % of D" in title and "step 2 mm" in title
    assert zoning_text("kmeans", {"zones": np.array([4.0])}, 1) == "kmeans with K = 4 gave 1 zone"
    assert zoning_text("amas", {"zones": np.array([0.15])}, 5) == "amas with k_lz = 0.15 gave 5 zones"
    assert zoning_text("none", {}, 1) == "none: 1 zone"


def test_the_cc_pattern_draws_x_y_and_z_on_one_scale(plan):
    problem, batch, genes = plan
    path = problem.planner.cl_path(genes, problem.feed_rate)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = cc_pattern_figure(problem.surface, path.info["cc"], path.pass_index, "t",
                                color=path.zone, color_label="zone", categories=2)
        fig.canvas.draw()
    ax3 = fig.axes[0]
    spans = np.array([np.ptp(ax3.get_xlim3d()), np.ptp(ax3.get_ylim3d()), np.ptp(ax3.get_zlim3d())])
    aspect = np.asarray(ax3.get_box_aspect())
    ratio = aspect / spans  # box length per mm, alike on every axis
    assert ratio.max() / ratio.min() < 1.3, (aspect, spans)
    plt.close(fig)


def test_the_cc_pattern_in_one_colour_warns_of_nothing(plan):
    """A plan without a per-point colour (a 3-axis single zone) draws its points in one colour
    and passes matplotlib no colour map it would warn is unused."""
    problem, batch, genes = plan
    path = problem.planner.cl_path(genes, problem.feed_rate)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = cc_pattern_figure(problem.surface, path.info["cc"], path.pass_index, "t")
        fig.canvas.draw()
    assert len(fig.axes) == 2  # no colour bar without a colour
    plt.close(fig)


def test_the_layers_legend_sits_outside_the_section():
    xs = np.linspace(0, 50, 51)
    X, Y = np.meshgrid(xs, xs)
    surface = 10 + 3 * np.sin(X / 8) * np.cos(Y / 10)
    stock = SimpleNamespace(grid=SimpleNamespace(xs=xs, ys=xs), z_surface=surface, z_top=16.0)
    floor = surface + 0.5
    layers = np.array([15.0, 13.0, 11.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = layers_figure(stock, floor, layers, "zlevel")
        fig.tight_layout()
        fig.canvas.draw()
    ax = fig.axes[1]
    legend = ax.get_legend()
    assert legend is not None and [t.get_text() for t in legend.get_texts()][:2] == ["stock top", "layers"]
    box, frame = legend.get_window_extent(), ax.get_window_extent()
    assert box.x0 >= frame.x1  # right of the section's axes: it covers no data
    plt.close(fig)
