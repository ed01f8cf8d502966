"""Study figures read back from the figure objects: the critical-difference diagram colours a
variant as every other figure does (not by rank), and a problem without a known optimum is
plotted in its own values (not as a precision against the best run, which spans 16 decades)."""

from __future__ import annotations

import re

import matplotlib.colors as mcolors
import numpy as np
import pandas as pd
import pytest

import evoplan.figure_style as style
from evoplan.study import figures
from evoplan.study.ranking import cd_diagram, friedman


def _capture(monkeypatch, module, name):
    seen = {}
    monkeypatch.setattr(module, name, lambda fig, *a, **k: seen.setdefault("fig", fig) and b"")
    return seen


def runs_frame(values: dict[str, np.ndarray], optimum=np.nan, problem="toolpath") -> pd.DataFrame:
    return pd.DataFrame([{"key": f"{a}.{r}", "problem": problem, "dimension": 3, "factor": "", "level": "",
                          "algorithm": a, "repetition": r, "status": "ok", "final_best": v, "optimum": optimum,
                          "budget": 100, "evaluations": 100}
                         for a, vs in values.items() for r, v in enumerate(vs)])


def test_cd_diagram_colours_follow_the_variant_not_its_rank(monkeypatch):
    rng = np.random.default_rng(0)
    base = rng.uniform(1, 2, 12)
    # study order ga, vega, de; ranks: de best, then vega, then ga
    runs = runs_frame({"ga": base + 1.0, "vega": base + 0.5, "de": base})
    _, _, diagrams = friedman(runs, "ga")
    colors = {n: s["color"] for n, s in figures.variant_styles(runs).items()}
    seen = _capture(monkeypatch, style, "png")
    cd_diagram(diagrams, 0.05, colors)
    ax = seen["fig"].axes[0]
    drawn = {t.get_text().strip("()0123456789. "): mcolors.to_hex(t.get_color()) for t in ax.texts}
    assert drawn == {"ga": style.PALETTE[0].lower(), "vega": style.PALETTE[1].lower(), "de": style.PALETTE[2].lower()}
    markers = {tuple(np.round(c.get_offsets()[0], 6)): mcolors.to_hex(c.get_facecolor()[0]) for c in ax.collections}
    ranks = diagrams[0][1]
    assert markers[(round(ranks["de"], 6), 0.0)] == style.PALETTE[2].lower()


def _history(key: str) -> pd.DataFrame:
    r = int(key.split(".")[1])
    return pd.DataFrame({"evaluations": [10.0, 50.0, 100.0], "best": np.array([0.8, 0.5, 0.3]) + 0.01 * r})


def test_convergence_without_a_known_optimum_shows_the_objective_not_a_16_decade_precision(monkeypatch):
    runs = runs_frame({"ga": [0.3, 0.31, 0.32], "vega": [0.3, 0.31, 0.32]})
    known = runs.groupby(["problem", "dimension"])["optimum"].first()
    seen = _capture(monkeypatch, figures, "_png")
    figures.convergence(runs, _history, known)
    ax = seen["fig"].axes[0]
    lo, hi = ax.get_ylim()
    assert ax.get_yscale() == "log" and 0.1 < lo < 0.3 and 0.8 < hi < 2, (lo, hi)
    assert ax.get_ylabel() == "f (best so far)"
    assert not [ln for ln in ax.get_lines() if ln.get_label().startswith("floor")]


def test_convergence_with_a_known_optimum_shows_precisions_floored(monkeypatch):
    runs = runs_frame({"ga": [0.3, 0.31, 0.32], "vega": [0.3, 0.31, 0.32]}, optimum=0.3, problem="kubota")
    known = runs.groupby(["problem", "dimension"])["optimum"].first()
    seen = _capture(monkeypatch, figures, "_png")
    figures.convergence(runs, _history, known)
    ax = seen["fig"].axes[0]
    assert ax.get_ylabel() == "f - f_opt (best so far)"
    assert [ln for ln in ax.get_lines() if ln.get_label().startswith("floor 1e-16: ")]  # run 0 hits f_opt


def tied_diagrams(n: int, panels: int = 2):
    """``panels`` families of ``n`` variants whose mean ranks tie in pairs and threes, with
    overlapping groups that Nemenyi does not separate (many crossbars)."""
    names = [f"variant {i:02d}" for i in range(n)]
    out = []
    for k in range(panels):
        ranks = pd.Series(1 + np.floor(np.arange(n) / (2 + k)) * (2 + k), index=names, dtype=float)
        ranks = ranks * (n + 1) / 2 / ranks.mean()                      # mean ranks average (n + 1) / 2
        if k == 3:
            ranks[:] = (n + 1) / 2                                       # all tied
        near = np.abs(ranks.to_numpy()[:, None] - ranks.to_numpy()[None, :]) <= n / 4
        out.append((f"problem {k}, 3-D", ranks, pd.DataFrame(np.where(near, 0.5, 0.001), index=names, columns=names)))
    return out


def saved_cd_figure(monkeypatch, diagrams):
    """The CD diagram's figure as saved (laid out by figure_style.png), and its renderer."""
    real, seen = style.png, {}

    def keep(fig):
        seen["fig"] = fig
        return real(fig)

    monkeypatch.setattr(style, "png", keep)
    data = cd_diagram(diagrams, 0.05)
    assert data[:4] == b"\x89PNG"
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    return seen["fig"], FigureCanvasAgg(seen["fig"]).get_renderer()     # png() closed its canvas


def test_cd_labels_of_tied_variants_never_overlap(monkeypatch):
    for n, panels in ((6, 1), (12, 2), (24, 3), (5, 4)):
        diagrams = tied_diagrams(n, panels)
        fig, renderer = saved_cd_figure(monkeypatch, diagrams)
        texts = [t for ax in fig.axes for t in [*ax.texts, ax.title] if t.get_text()]
        assert len(texts) == panels * (n + 1)                            # every label, every title
        for ax, (_, ranks, _) in zip(fig.axes, diagrams):               # each label's rank, to 3 digits
            for t in ax.texts:
                name = re.sub(r"\s*\([^)]*\)\s*", "", t.get_text())
                shown = float(re.search(r"\(([^)]*)\)", t.get_text()).group(1))
                assert shown == pytest.approx(ranks[name], rel=5e-3), t.get_text()
        boxes = [t.get_window_extent(renderer) for t in texts]
        for i, a in enumerate(boxes):
            for j in range(i + 1, len(boxes)):
                b = boxes[j]
                overlap_x = min(a.x1, b.x1) - max(a.x0, b.x0)
                overlap_y = min(a.y1, b.y1) - max(a.y0, b.y0)
                assert overlap_x <= 0 or overlap_y <= 0, (n, texts[i].get_text(), texts[j].get_text())
        for ax in fig.axes:                                              # the rows of one side: spaced
            for side in ("left", "right"):
                ys = sorted(t.get_window_extent(renderer).y0 for t in ax.texts if t.get_ha() == side)
                height = max(t.get_window_extent(renderer).height for t in ax.texts)
                assert np.diff(ys).min() >= 1.3 * height, (n, side)
