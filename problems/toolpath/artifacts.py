"""Result files of one toolpath plan: the zone map, the CC pattern and the APT CL program.

Every configuration of the toolpath problem writes the three (a single zone is a zone map
of one zone): the zone map draws the zones on the parametric mesh in plan view, their
borders and the sections actually cut (the CC points of each section joined in machining
order), each zone labelled with its feed direction and cutting length; the CC pattern
(``figures.cc_pattern_png``) colours the CC points by zone, or by chord error for one zone (5-axis);
the APT program (``export.apt_write.apt_plan``) has the title and the surface
(``export.toolpath.surface_comment``: a mesh's fit deviation) as header comments and opens
each section with a ``$$ ZONE z PASS k`` comment, entered from and left to the safe height. ``toolpath.npz`` holds
what ``evoplan report`` draws beside the APT program's moves: the CC points with their zone and
pass, one per CL point of the path (``cc``: the run-on / run-off points past the part's edge,
into a trimmed face's holes and notches, included: each is its section's end CC point shifted
along the travel), ``on_part`` (False for those), ``inserted`` (True for a point the chord
refinement added, its ``on_part`` its left neighbour's), the part sampled on a (u, v)
grid, the tolerance and the plan's analytic criteria (names and values; the units are the
criteria table's). ``cc_count`` counts the plan's points on the part: ``on_part & ~inserted``.
"""

from __future__ import annotations

import io
import textwrap

import numpy as np

from .criteria.analytic import eq4_total, plan_lengths

__all__ = ["plan_artifacts", "zone_map_figure", "zone_map_png", "report_data", "zoning_text"]

REPORT_MESH = 61  # (u, v) samples per side of the part in toolpath.npz


def zoning_text(method: str, genes: dict, zones: int) -> str:
    """What the zoning made, against what its gene asked: ``kmeans with K = 4 gave 1 zone``
    (the zones of K-means are split into connected parts and then merged by Eq. 4, so the
    count differs from K)."""
    made = f"{zones} zone{'s' if zones != 1 else ''}"
    if "zones" not in genes:
        return f"{method}: {made}"
    symbol = {"kmeans": "K", "amas": "k_lz"}.get(method, "zones")
    return f"{method} with {symbol} = {float(genes['zones'][0]):.4g} gave {made}"


def _title(problem, genes, batch) -> str:
    from evoplan.figure_style import gene_text

    parts = []
    for name, value in genes.items():
        v = value[0]
        if name == "tool":
            tool = problem.tool_db.tools[int(v)]
            parts.append(f"tool {tool.id} ({tool.label()})")
        elif name != "zones":
            parts.append(gene_text(name, float(v)))
    zones = int(batch.zones[0])
    cutting = float(plan_lengths(batch)["cutting_length"][0])
    parts.append(f"{problem.machine}, {zoning_text(problem.planner.layouts.method.name, genes, zones)}, "
                 f"cutting {cutting:.1f} mm, Eq. 4 total {eq4_total(cutting, zones, problem.delta_l):.1f} mm")
    return ", ".join(parts)


def plan_limits(corners: np.ndarray, lines: list, margin: float = 0.03) -> tuple[tuple, tuple]:
    """x and y limits holding the part (``corners``) and every drawn section, run-on and
    run-off past the part's edges included, with ``margin`` of the span on each side."""
    xy = np.concatenate([corners[..., :2].reshape(-1, 2), *lines]) if lines else corners[..., :2].reshape(-1, 2)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = margin * (hi - lo).max()
    return (lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad)


def zone_map_figure(surface, batch, labels, title: str = ""):
    """Plan 0 of ``batch`` in plan view (XY): its zones (``labels`` (n, m) on the parametric
    mesh, or None for one zone) with their borders, and its sections, all inside the axes."""
    from evoplan.figure_style import figure  # sets the Agg backend before pyplot loads

    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    from .plan.zoning.figures import border_segments

    labels = np.zeros((24, 24), int) if labels is None else np.asarray(labels)
    n, m = labels.shape
    zones = int(batch.zones[0])
    gu, gv = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, m + 1), indexing="ij")
    corners = surface.points(gu.ravel(), gv.ravel()).reshape(n + 1, m + 1, 3)
    fig, (ax,) = figure(1, width=7.5, height=8)
    ax.grid(False)
    cmap = plt.get_cmap("tab20", max(zones, 1))
    ax.pcolormesh(corners[..., 0], corners[..., 1], labels, cmap=cmap, alpha=0.35,
                  vmin=-0.5, vmax=zones - 0.5, shading="flat")
    ax.add_collection(LineCollection(border_segments(labels, corners), colors="k", linewidths=1.2))
    secs = np.flatnonzero(batch.sec_ind == 0)
    lines = [batch.p[batch.sec_start[s]:batch.sec_start[s] + batch.sec_count[s], :2] for s in secs]
    ax.add_collection(LineCollection(lines, colors=[cmap(int(batch.sec_zone[s])) for s in secs],
                                     linewidths=0.8))
    seg_zone = batch.sec_zone[batch.seg_sec]
    for z in range(zones):
        own = secs[batch.sec_zone[secs] == z]
        if len(own) == 0:
            continue
        pts = np.concatenate([lines[i] for i in np.flatnonzero(batch.sec_zone[secs] == z)])
        length = batch.seg_len[(batch.sec_ind[batch.seg_sec] == 0) & (seg_zone == z)].sum()
        deg = np.degrees(batch.sec_alpha[own[0]]) % 180
        cx, cy = pts.mean(axis=0)
        ax.annotate(f"{z}: {deg:.0f}°\n{length:.0f} mm", (cx, cy), ha="center", va="center",
                    fontsize=7, bbox=dict(boxstyle="round", fc="white", alpha=0.7, lw=0))
    xlim, ylim = plan_limits(corners, lines)
    ax.set(xlim=xlim, ylim=ylim, xlabel="X (mm)", ylabel="Y (mm)")
    ax.set_aspect("equal")
    ax.set_title("\n".join(textwrap.wrap(title, 90)), fontsize=8)
    return fig


def zone_map_png(surface, batch, labels, title: str = "") -> bytes:
    """:func:`zone_map_figure` as PNG bytes."""
    from evoplan.figure_style import png

    return png(zone_map_figure(surface, batch, labels, title))


def report_data(problem, batch, genes, path) -> bytes:
    """``toolpath.npz`` (see the module docstring): data only, read back with ``allow_pickle=False``."""
    from .criteria.analytic import analytic_criteria

    crit = analytic_criteria(batch, problem.surface, problem.tool_db, genes, allowance=problem.allowance,
                             feed_rate=problem.feed_rate, delta_l=problem.delta_l, machine=problem.machine)
    u, v = np.meshgrid(np.linspace(0, 1, REPORT_MESH), np.linspace(0, 1, REPORT_MESH), indexing="ij")
    mesh = problem.surface.points(u.ravel(), v.ravel()).reshape(REPORT_MESH, REPORT_MESH, 3)
    names = sorted(crit)
    buf = io.BytesIO()
    cc = np.asarray(path.info["cc"], float)
    on_part = np.asarray(path.info.get("on_part", np.ones(len(cc), bool)), bool)
    inserted = np.asarray(path.info.get("inserted", np.zeros(len(cc), bool)), bool)
    np.savez_compressed(buf, cc=cc, on_part=on_part, inserted=inserted, zone=path.zone,
                        pass_index=path.pass_index,
                        surface=mesh, tolerance=float(problem.tolerance),
                        criteria_names=np.array(names), criteria_values=np.array([float(crit[k][0]) for k in names]))
    return buf.getvalue()


def plan_artifacts(problem, batch, genes, path) -> dict[str, bytes]:
    """``zone_map.png``, ``cc_pattern.png`` and ``toolpath.apt`` of plan 0 of ``batch``
    (``path``: its CLPath as the machine runs it); the title's lengths are the plan's own."""
    from .export.apt_write import apt_plan
    from .export.toolpath import surface_comment
    from .figures import cc_pattern_png

    tool = problem.tool_db.tools[int(genes["tool"][0])]
    title = _title(problem, genes, batch)
    zones = int(batch.zones[0])
    if zones > 1:
        color, label, categories = path.zone, "zone", zones
    else:  # the plan's chord errors, when the CL path holds the plan's points as they are
        idx = batch.points_of(0)
        chord = batch.chord[idx] if len(idx) == len(path) else None
        color, label, categories = chord, "chord error (mm)" if chord is not None else "", None
    apt = apt_plan(path, tool, comments=[*textwrap.wrap(title, 66),
                                         surface_comment(problem.surface, problem.spec.surface)])
    return {
        "zone_map.png": zone_map_png(problem.surface, batch, problem.labels(genes), title),
        "cc_pattern.png": cc_pattern_png(problem.surface, path.info["cc"], path.pass_index,
                                         title="\n".join(textwrap.wrap(title, 110)),
                                         color=color, color_label=label,
                                         categories=categories),
        "toolpath.apt": apt.encode(),
        "toolpath.npz": report_data(problem, batch, genes, path),
    }
