"""Study figures read back from the figure objects: the critical-difference diagram colours a
variant as every other figure does (not by rank), and a problem without a known optimum is
plotted in its own values (not as a precision against the best run, which spans 16 decades)."""

from __future__ import annotations

import matplotlib.colors as mcolors
import numpy as np
import pandas as pd

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
