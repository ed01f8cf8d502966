"""Figure geometry, read back from the Axes: the generation axis, the style, floors, points."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from evoplan.figure_style import PALETTE, boxes, mark_floor, variant_style
from evoplan.plots import convergence_figure


def _history(per_generation):
    evals = np.cumsum(per_generation)
    n = len(evals)
    return pd.DataFrame({"generation": np.arange(n), "evaluations": evals,
                         "best": np.geomspace(1.0, 1e-3, n), "mean": np.geomspace(2.0, 1e-2, n)})


def test_generation_ticks_sit_at_the_evaluations_where_generations_ended():
    # like a VEGA run: 20 for the initial population, then an uneven count per generation
    rng = np.random.default_rng(0)
    history = _history(np.r_[20, rng.integers(100, 140, size=50)])
    fig = convergence_figure(history, "t")
    ax, top = fig.axes[0], fig.axes[1]
    assert top.get_xlabel() == "generation"
    assert top.get_xlim() == ax.get_xlim()  # the two axes share one evaluation scale
    ticks = top.get_xticks()
    labels = [int(t.get_text()) for t in top.get_xticklabels()]
    assert len(ticks) >= 4 and labels[0] == 0 and labels[-1] <= 50
    by_gen = dict(zip(history["generation"], history["evaluations"]))
    for at, g in zip(ticks, labels):
        assert at == by_gen[g]  # generation g's tick at the evaluation count of its history row
    lo, hi = ax.get_xlim()
    assert lo <= ticks.min() and ticks.max() <= hi
    plt.close(fig)


def test_many_variants_differ_in_colour_and_marker_on_a_colour_blind_safe_palette():
    styles = [variant_style(i) for i in range(16)]
    assert len({(s["color"], s["marker"]) for s in styles}) == 16
    assert len({(s["color"], s["marker"], s["linestyle"]) for s in styles}) == 16
    assert {s["color"] for s in styles} <= set(PALETTE)


def test_floor_and_small_boxes_are_shown():
    fig, ax = plt.subplots()
    boxes(ax, [np.array([1.0, 2.0, 3.0]), np.arange(100.0)], ["few", "many"])
    dots = [line for line in ax.lines if line.get_linestyle() == "None"]
    assert len(dots) == 1 and len(dots[0].get_xdata()) == 3  # points for the small box only
    mark_floor(ax, 1e-16, 4)
    assert any("4 values at or below" in t for t in ax.get_legend_handles_labels()[1])
    plt.close(fig)


def test_generations_that_cost_no_evaluation_share_one_tick():
    history = _history([8, 6, 0, 0, 1, 2, 1])  # generations 2-3 answered by the cache
    fig = convergence_figure(history, "t")
    ax, top = fig.axes
    ticks, labels = top.get_xticks(), [t.get_text() for t in top.get_xticklabels()]
    assert len(set(ticks)) == len(ticks) and "3" in labels and "1" not in labels and "2" not in labels
    assert ax.get_ylabel() == "objective (minimized)"
    plt.close(fig)


def test_generation_labels_do_not_collide_where_generations_cost_few_evaluations():
    # like runs/kubota_vega.yaml: the cache answers most of the late generations ("3240 48")
    per = np.r_[20, np.full(20, 40), np.full(30, 3)]
    history = _history(per)
    fig = convergence_figure(history, "t")
    fig.tight_layout()
    fig.canvas.draw()
    top = fig.axes[1]
    renderer = fig.canvas.get_renderer()
    boxes_ = sorted((t.get_window_extent(renderer) for t in top.get_xticklabels() if t.get_text()),
                    key=lambda b: b.x0)
    assert len(boxes_) >= 4
    assert all(a.x1 < b.x0 for a, b in zip(boxes_, boxes_[1:]))  # no two labels overlap
    assert top.get_xticklabels()[-1].get_text() == str(history["generation"].max())  # the run's end
    plt.close(fig)
