"""One style for every evoplan figure: palette, markers, units, legends, floors, bands, PNG output.

- **Colours**: the Okabe-Ito palette (8 colours told apart with the common colour-vision
  deficiencies); variant ``i`` takes colour ``i mod 8``, marker ``i mod 7`` and a dashed line
  from the ninth on, so up to 56 variants differ in colour *and* marker, and 16 in all three.
- **Zones** of a plan take the palette without its black (:func:`zone_colors`), up to 7;
  more zones than that take matplotlib's tab20 (20 hues; the black borders tell them apart).
- **Legends** go outside the data, to the right of the axes (:func:`legend_outside`).
- **Units**: :func:`label` names a criterion with its unit (``machining error (mm)``), and
  :func:`gene_text` a decision with its own (``step-over 30 % of D``, ``lead 2°``); lengths
  are mm, times min, angles degrees. Axes with a unit print plain numbers (``1300``, not ``1.3x10^3``).
- **Floors**: a value clamped to a floor on a log axis is drawn there with a dotted line that
  says so (:func:`mark_floor`).
- **Bands** say what they are in their legend entry (:func:`band_label`).
- **Box plots** show every point when a box holds few (:func:`boxes`).
"""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402

from .units import GENE_UNITS  # noqa: E402

#: Okabe & Ito (2008), "Color Universal Design"; black last (it doubles as the text colour)
PALETTE = ("#E69F00", "#56B4E9", "#009E73", "#F0E442", "#0072B2", "#D55E00", "#CC79A7", "#000000")
MARKERS = ("o", "s", "^", "D", "v", "P", "X")
LINESTYLES = ("-", "--", ":", "-.")
#: points drawn over a box when it holds at most this many values
POINTS_UP_TO = 30
#: the resolution of every figure (:func:`figure`), hence of every PNG (:func:`png`)
DPI = 110

#: units of the criteria evoplan reports (toolpath problems), by name
UNITS = {
    "machining_error": "mm", "machining_error_mean": "mm", "chord_error_mean": "mm",
    "chord_error_max": "mm", "scallop_max": "mm", "scallop_mean": "mm", "gouge_max": "mm",
    "undercut_max": "mm", "cutting_length": "mm", "link_length": "mm", "path_length": "mm",
    "total_length": "mm", "machining_time": "min", "cc_count": "CC points", "n_passes": "passes",
}


def variant_style(i: int) -> dict:
    """Colour, marker and line style of variant ``i`` (see the module docstring)."""
    return {"color": PALETTE[i % len(PALETTE)], "marker": MARKERS[i % len(MARKERS)],
            "linestyle": LINESTYLES[(i // len(PALETTE)) % len(LINESTYLES)]}


def zone_colors(n: int) -> list:
    """Fill / pass colours of ``n`` zones (see the module docstring), as RGBA tuples."""
    from matplotlib.colors import to_rgba

    if n <= len(PALETTE) - 1:
        return [to_rgba(c) for c in PALETTE[:-1][:max(n, 1)]]
    cmap = plt.get_cmap("tab20", n)
    return [tuple(cmap(i)) for i in range(n)]


def label(name: str, unit: str | None = None) -> str:
    """``"machining_error"`` -> ``"machining error (mm)"``; ``unit`` overrides the table."""
    unit = unit if unit is not None else UNITS.get(name)
    text = name.replace("_", " ")
    return f"{text} ({unit})" if unit else text


def gene_text(name: str, value: float) -> str:
    """A decision with its unit: ``step-over 30 % of D``, ``lead 2.5°``, ``step 2 mm``."""
    unit = GENE_UNITS.get(name, "")
    text = "step-over" if name == "stepover" else name.replace("_", " ")
    number = f"{value:.4g}"
    if unit == "deg":
        return f"{text} {number}°"
    return f"{text} {number} {unit}" if unit and unit != name else f"{text} {number}"


def plain_numbers(ax, axis: str = "y") -> None:
    """Tick labels as plain numbers (``1300``, ``0.02``), also on a log axis."""
    target = ax.yaxis if axis == "y" else ax.xaxis
    target.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    if target.get_scale() == "log":  # few decades: label minor ticks too (all under one decade)
        lo, hi = sorted(target.get_view_interval())
        decades = np.log10(hi / lo) if lo > 0 else np.inf

        def minor(v, _):
            if v <= 0 or decades >= 1.5:
                return ""
            mantissa = v / 10 ** np.floor(np.log10(v) + 1e-9)
            keep = decades < 1 or any(abs(mantissa - k) < 1e-6 for k in (2, 3, 5))
            return f"{v:g}" if keep else ""

        target.set_minor_formatter(FuncFormatter(minor))


def band_label(what: str, n: int) -> str:
    """Legend text of a band: what it spans, over how many runs."""
    return f"{what} of {n} run{'s' if n != 1 else ''}"


def mark_floor(ax, floor: float, clamped: int) -> None:
    """Say on the axes that ``clamped`` plotted values were below ``floor`` and drawn at it."""
    if clamped:
        ax.axhline(floor, color="0.4", lw=0.8, ls=":", zorder=0,
                   label=f"floor {floor:g}: {clamped} value{'s' if clamped != 1 else ''} at or below, drawn here")


def legend_outside(ax, title: str | None = None, fontsize: float = 7) -> None:
    """The legend of ``ax`` to the right of the axes, outside the data."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0,
                  fontsize=fontsize, title=title, title_fontsize=fontsize, frameon=False)


def figure_legend(fig, fontsize: float = 7) -> None:
    """One legend for every panel of ``fig`` (each label once), to the right of the panels."""
    seen: dict = {}
    for ax in fig.axes:
        for handle, text in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(text, handle)
    if seen:
        fig.legend(list(seen.values()), list(seen), loc="upper left", bbox_to_anchor=(1.0, 1.0),
                   fontsize=fontsize, frameon=False)


def boxes(ax, data: list, labels: list, rng_seed: int = 0) -> None:
    """Box plots of ``data`` (one array per label), with every point when there are few."""
    ax.boxplot([np.asarray(d, dtype=float) for d in data], tick_labels=labels, showfliers=False,
               medianprops={"color": PALETTE[5]})
    jitter = np.random.default_rng(rng_seed)  # only spreads points sideways, deterministic
    for i, d in enumerate(data, start=1):
        d = np.asarray(d, dtype=float)
        if 0 < d.size <= POINTS_UP_TO:
            x = i + jitter.uniform(-0.12, 0.12, d.size)
            ax.plot(x, d, ls="none", marker=MARKERS[0], ms=3.5, alpha=0.7, color=PALETTE[4])


def figure(n: int = 1, width: float = 4.6, height: float = 3.4, cols: int = 3):
    """A figure with ``n`` panels on a grid of at most ``cols`` columns; ``(fig, [axes])``."""
    cols = max(1, min(n, cols))
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), dpi=DPI, squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax in axes.flat[:n]:
        ax.grid(True, which="major", alpha=0.3)
    return fig, list(axes.flat[:n])


def png(fig) -> bytes:
    """PNG bytes of ``fig`` (legends outside included), and the figure closed.

    The panels are laid out without the outside legends (so they keep their width), and the
    saved image is then widened to hold them."""
    legends = [leg for ax in fig.axes if (leg := ax.get_legend()) is not None]
    for leg in legends:
        leg.set_visible(False)
    fig.tight_layout()
    for leg in legends:
        leg.set_visible(True)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", bbox_inches="tight")
    plt.close(fig)
    return buf.getvalue()
