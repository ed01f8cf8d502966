"""More than two variants at once: Friedman test, Nemenyi post-hoc, critical-difference diagram;
and the Bayesian signed-rank test of each variant against the reference.

**Friedman / Nemenyi** (Demšar 2006). Within each test family (a problem and dimension; for a
factor study, the levels of one factor, as in ``statistics.py``) the repetitions are the
blocks: repetition ``r`` of every variant ran from the same seed. Each block ranks the variants
by final value (failed runs last, ties share the average rank). The Friedman test
(``scipy.stats.friedmanchisquare``) asks whether any variant differs; the Nemenyi post-hoc
test on the same ranks (``scikit_posthocs.posthoc_nemenyi_friedman``) gives every pair's
p-value, and the critical-difference diagram (``scikit_posthocs.critical_difference_diagram``)
draws the mean ranks with a bar joining the variants no pair test separates. Only families of
three or more variants are tested.

**Bayesian signed-rank test** (Benavoli et al. 2014, ``baycomp.SignedRankTest``): on the
differences paired by repetition, the posterior probabilities that the variant is better
(lower), practically equivalent (within ``rope``, in objective units; only when ``rope > 0``)
or worse than the reference. It states how likely each outcome is, rather than whether a
null hypothesis is rejected. With ``rope = 0`` there is no equivalence region and a zero
difference counts half for each side, so on data with many ties (runs that all reach the same
value) a single non-zero difference decides the outcome: set ``statistics.rope`` (in objective
units) for such problems.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy import stats

from .statistics import families, value_matrix

FRIEDMAN_COLUMNS = ["problem", "dimension", "factor", "variants", "n", "statistic", "p_value"]
BAYES_COLUMNS = ["problem", "dimension", "factor", "reference", "algorithm", "level", "n", "rope",
                 "p_better", "p_equivalent", "p_worse"]


def _label(factor: str, key: tuple[str, str]) -> str:
    return key[0] if not factor else f"{factor}={key[1]}"


def friedman(runs: pd.DataFrame, reference: str, reference_levels: dict[str, str] | None = None):
    """``(friedman table, nemenyi table, diagrams)``; a diagram is ``(title, mean ranks, p matrix)``."""
    rows, pairs, diagrams = [], [], []
    for (problem, dimension), factor, ref, others in families(runs, reference, reference_levels or {}):
        variants = [ref, *others]
        if len(variants) < 3:
            continue
        labels = [_label(factor, key) for key, _ in variants]
        values = value_matrix(variants)  # (repetitions, variants), failed runs inf
        values = values[~np.isnan(values).any(axis=1)]
        if len(values) < 2:
            continue
        ranks = pd.DataFrame(stats.rankdata(values, axis=1), columns=labels)
        if np.ptp(ranks.to_numpy(), axis=1).max() == 0:  # every block a tie: nothing to test
            statistic, p = 0.0, 1.0
            p_matrix = pd.DataFrame(1.0, index=labels, columns=labels)
        else:
            res = stats.friedmanchisquare(*values.T)
            statistic, p = float(res.statistic), float(res.pvalue)
            import scikit_posthocs as sp

            p_matrix = sp.posthoc_nemenyi_friedman(ranks)
        rows.append({"problem": problem, "dimension": dimension, "factor": factor, "variants": len(labels),
                     "n": len(values), "statistic": statistic, "p_value": p})
        for i, a in enumerate(labels):
            for b in labels[i + 1:]:
                pairs.append({"problem": problem, "dimension": dimension, "factor": factor, "a": a, "b": b,
                              "mean_rank_a": ranks[a].mean(), "mean_rank_b": ranks[b].mean(),
                              "p_nemenyi": float(p_matrix.loc[a, b])})
        title = f"{problem}, {dimension}-D" + (f", {factor}" if factor else "")
        diagrams.append((title, ranks.mean(), p_matrix))
    return (pd.DataFrame(rows, columns=FRIEDMAN_COLUMNS), pd.DataFrame(pairs), diagrams)


#: a CD diagram's label font (pt), and the least distance between two label rows, in label
#: font sizes (centre to centre: a row of 9 pt text is about 1.2 font sizes tall)
CD_FONT = 9
CD_ROW = 1.7
#: inches of a CD panel outside its label rows: the title, the rank axis and its tick labels
CD_FRAME = 0.95


def cd_figure(diagrams, alpha: float = 0.05, colors: dict[str, str] | None = None, left_out: str = ""):
    """The critical-difference diagrams of :func:`friedman`, one panel each (see :func:`cd_diagram`).

    scikit-posthocs puts each label on a row of its own, one data unit apart, under the
    crossbars; each panel is made tall enough that its rows stay :data:`CD_ROW` font sizes
    apart whatever the number of variants, ties and crossbars, so no two labels overlap (ties
    used to crowd a fixed 2.5 in panel). The rank axis spans 1 to the number of variants."""
    import scikit_posthocs as sp

    from ..figure_style import PALETTE, figure

    colors = dict(colors or {})
    fig, axes = figure(len(diagrams), width=8, height=2.5, cols=1)
    heights = []
    for ax, (title, ranks, p_matrix) in zip(axes, diagrams):
        for name in ranks.index:
            colors.setdefault(name, PALETTE[len(colors) % len(PALETTE)])
        ax.grid(False)
        lo = min(1.0, float(ranks.min()))
        hi = max(float(len(ranks)), float(ranks.max()))
        # labels a gap off their end of the ranks (all tied: the two sides' labels stay apart), the
        # rank to 3 digits (2 wrote 10.5 as 10)
        sp.critical_difference_diagram(ranks, p_matrix, alpha=alpha, ax=ax, label_props={"fontsize": CD_FONT},
                                       color_palette={n: colors[n] for n in ranks.index},
                                       text_h_margin=0.015 * (hi - lo), label_fmt_left="{label} ({rank:.3g})",
                                       label_fmt_right="({rank:.3g}) {label}")
        ax.set_xlim(lo - 0.02 * (hi - lo), hi + 0.02 * (hi - lo))
        bottom = min(y for line in ax.get_lines() for y in line.get_ydata())  # the lowest label row
        ax.set_ylim(bottom - 0.7, 0.6)
        ax.set_title(f"{title}: mean rank (1 = best); a bar joins variants not separated at alpha = {alpha}",
                     fontsize=9)
        heights.append(CD_FRAME + (0.6 - bottom + 0.7) * CD_ROW * CD_FONT / 72)
    if len(axes) > 1:
        axes[0].get_subplotspec().get_gridspec().set_height_ratios(heights)
    fig.set_figheight(sum(heights))
    if left_out:
        fig.text(0.01, -0.02, f"left out (failed runs): {left_out}", ha="left", va="top", fontsize=8, wrap=True)
    return fig


def cd_diagram(diagrams, alpha: float = 0.05, colors: dict[str, str] | None = None, left_out: str = "") -> bytes:
    """The critical-difference diagrams of :func:`friedman`, one panel each, as PNG bytes
    (:func:`cd_figure`).

    ``left_out`` names the variants with failed runs that the ranks leave out (a caption under
    the panels, so the figure does not read as if they had never been run).

    ``colors`` maps a variant's label to its colour in the study's other figures
    (:func:`evoplan.study.figures.variant_styles`), so a variant keeps its colour here too,
    whatever its rank; a label it lacks takes the palette's next colour."""
    from ..figure_style import png

    return png(cd_figure(diagrams, alpha, colors, left_out))


def bayesian(runs: pd.DataFrame, reference: str, reference_levels: dict[str, str] | None = None,
             rope: float = 0.0, nsamples: int = 20000, seed: int = 0) -> pd.DataFrame:
    """``bayes.csv``: every variant against the reference of its family (see the module docstring)."""
    import baycomp

    out = []
    for (problem, dimension), factor, ref, others in families(runs, reference, reference_levels or {}):
        for variant in others:
            values = value_matrix([variant, ref])
            values = values[np.isfinite(values).all(axis=1)]
            x, y = values[:, 0], values[:, 1]
            row = {"problem": problem, "dimension": dimension, "factor": factor,
                   "reference": _label(factor, ref[0]), "algorithm": variant[0][0], "level": variant[0][1],
                   "n": len(x), "rope": rope, "p_better": np.nan, "p_equivalent": np.nan, "p_worse": np.nan}
            if len(x) >= 2 and np.any(x != y):
                # baycomp works on y - x: "right" is reference - variant > rope, the variant lower
                probs = baycomp.SignedRankTest.probs(x, y, rope=rope, nsamples=nsamples, random_state=seed)
                if rope > 0:
                    row.update(p_worse=probs[0], p_equivalent=probs[1], p_better=probs[2])
                else:
                    row.update(p_worse=probs[0], p_better=probs[1])
            elif len(x):
                row.update(p_better=0.0, p_worse=0.0, p_equivalent=1.0)
            out.append(row)
    return pd.DataFrame(out, columns=BAYES_COLUMNS)
