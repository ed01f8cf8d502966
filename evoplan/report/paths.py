"""Toolpaths in 3D: an operation's moves read from its APT file, drawn with plotly.

The moves come from the folder's APT CL files (the program the machine runs): a move into a
point is a rapid (``RAPID``), a link (a feed move slower than the operation's cutting feed:
plunges, entries and exits) or a cut. Cuts are coloured by zone (hue) and pass (shade), or by
layer for roughing; links and rapids are dashed. Cut polylines are decimated for display
(``decimate.fit_budget``) and the figure says within which tolerance.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .decimate import fit_budget

__all__ = ["Moves", "read_moves", "toolpath_figure", "surface_trace", "stl_trace"]

GROUP = re.compile(r"^\s*\$\$\s*(ZONE\s+(\d+)\s+)?(PASS|LAYER)\s+(\d+)", re.I)
MOTION = re.compile(r"^\s*(GOTO|GODLTA)\b", re.I)
POINT_BUDGET = 60_000        # cut points drawn per figure, at most
MARKER_BUDGET = 20_000       # CL / CC markers drawn, at most
OPERATION_HUE = ["#1565c0", "#2e7d32", "#6a1b9a", "#00838f"]
SEQ = ["Blues", "Oranges", "Greens", "Purples", "Reds", "Greys", "YlOrBr", "PuRd"]
ZONE_HUE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#d62728", "#7f7f7f", "#bcbd22", "#e377c2"]


@dataclass
class Moves:
    """One operation: per point (file order) the tip, axis, move kind into it and its group."""

    name: str
    tip: np.ndarray
    axis: np.ndarray
    kind: np.ndarray          # 0 cut, 1 link, 2 rapid (the move INTO the point; point 0: rapid)
    zone: np.ndarray          # zone number (or layer number), -1 before any group comment
    pass_index: np.ndarray    # pass number (0 for a layer)
    group_word: str           # "zone" or "layer"
    diameter: float
    feed: float               # the cutting feed (mm/min): the most frequent one

    @property
    def multi_axis(self) -> bool:
        return bool(len(self.axis) and np.ptp(self.axis, axis=0).max() > 1e-6)


def read_moves(path: Path, name: str | None = None) -> Moves:
    """The moves of one APT file (see the module docstring); ``AptError`` if unreadable."""
    from ..problems.toolpath.export.apt_read import read_apt

    apt = read_apt(path)
    text = Path(path).read_text(encoding="utf-8")
    word = "zone"
    count, zone, pas = 0, -1, 0
    marks = []                               # (motions before, zone, pass)
    for line in text.splitlines():
        if MOTION.match(line):
            count += 1
        elif m := GROUP.match(line):
            w = m.group(3).upper()
            if w == "LAYER":
                word, zone, pas = "layer", int(m.group(4)), 0
            else:
                zone, pas = (int(m.group(2)) if m.group(2) else 0), int(m.group(4))
            marks.append((count, zone, pas))
    m = len(apt.tip)
    zone_of = np.full(m, -1, np.int64)
    pass_of = np.zeros(m, np.int64)
    for start, z, p in marks:
        zone_of[start:] = z
        pass_of[start:] = p
    feed = np.nan_to_num(np.asarray(apt.feed, float), nan=0.0)
    rapid = np.asarray(apt.rapid, bool).copy()
    if m:
        rapid[0] = True
    cutting = feed[~rapid]
    main_feed = 0.0
    if cutting.size:
        values, counts = np.unique(cutting, return_counts=True)
        main_feed = float(values[counts.argmax()])
    kind = np.where(rapid, 2, np.where(feed < main_feed - 1e-9, 1, 0))
    return Moves(name or Path(path).stem, apt.tip, apt.axis, kind, zone_of, pass_of, word,
                 float(apt.cutter.diameter) if apt.cutter is not None else float("nan"), main_feed)


def _cut_runs(mv: Moves) -> tuple[np.ndarray, np.ndarray]:
    """(point indices, run id) of the cut polylines: each run is a chain of cut moves with the
    point it starts from, within one zone and pass."""
    cut = mv.kind == 0
    cut[0] = False
    grp = mv.zone * 100_003 + mv.pass_index
    new = cut & ~np.r_[False, cut[:-1]] | cut & (np.r_[0, np.diff(grp)] != 0)
    starts = np.flatnonzero(new)
    idx = np.flatnonzero(cut)
    run = np.cumsum(new)[idx]
    # prepend each run's start point (the point the first cut move leaves from)
    idx = np.concatenate([idx, starts - 1])
    run = np.concatenate([run, np.cumsum(new)[starts]])
    order = np.lexsort((idx, run))
    return idx[order], run[order]


def _nan_join(points: np.ndarray, run: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points with a NaN row after each run (plotly breaks a line at NaN); (xyz, is_gap)."""
    brk = np.flatnonzero(np.diff(run) != 0) + 1
    out = np.insert(points, brk, np.nan, axis=0)
    return out, np.isnan(out[:, 0])


def _segments(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Segments a[i] -> b[i] as one NaN-separated polyline (3 rows each)."""
    out = np.full((3 * len(a), 3), np.nan)
    out[0::3], out[1::3] = a, b
    return out


def _line3d(xyz, name, **kw):
    import plotly.graph_objects as go

    return go.Scatter3d(x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2], mode="lines", name=name, **kw)


def add_moves(fig, mv: Moves, *, prefix: str = "", cc: np.ndarray | None = None,
              colour: str | None = None) -> dict:
    """Add ``mv``'s traces to ``fig``; returns the display figures (points, kept, tolerance)."""
    import plotly.graph_objects as go

    idx, run = _cut_runs(mv)
    keep, tol = fit_budget(mv.tip[idx], run, POINT_BUDGET)
    idx, run = idx[keep], run[keep]
    word = mv.group_word
    # a run's first point is where it starts from (a rapid's or the previous pass's end): it
    # belongs to the run's zone and pass, those of the run's last point
    last = np.r_[np.flatnonzero(np.diff(run) != 0), len(run) - 1] if len(run) else np.array([], int)
    of_run = np.cumsum(np.r_[0, np.diff(run) != 0]) if len(run) else np.array([], int)
    zone, pass_of = mv.zone[idx][last][of_run], mv.pass_index[idx][last][of_run]
    groups = np.unique(zone) if len(idx) else np.array([], int)
    if colour is not None:  # one trace for all the operation's cuts
        groups = groups[:1]
    for k, z in enumerate(groups):
        sel = zone == z if colour is None else np.ones(len(idx), bool)
        pts, gap = _nan_join(mv.tip[idx[sel]], run[sel])
        passes = np.insert(pass_of[sel], np.flatnonzero(np.diff(run[sel]) != 0) + 1, 0)
        label = f"{prefix}{word} {z}" if z >= 0 and colour is None else f"{prefix}cuts"
        hover = [f"{label}, pass {p}" if word == "zone" else label for p in passes]
        line = dict(width=3)
        if colour is not None:
            line["color"] = colour
        elif word == "zone":
            line.update(color=passes, colorscale=SEQ[k % len(SEQ)], cmin=-max(passes.max(), 1),  # pass 0 mid-scale
                        cmax=max(passes.max(), 1))
        else:
            line["color"] = ZONE_HUE[k % len(ZONE_HUE)]
        fig.add_trace(_line3d(pts, label, line=line, text=hover, legendgroup=f"{prefix}{word}{z}",
                              hovertemplate="%{text}<br>x %{x:.3f} mm<br>y %{y:.3f} mm<br>z %{z:.3f} mm<extra></extra>"))
    for kind, label, col in ((1, "links (entry, exit, plunge)", "#e65100"), (2, "rapids", "#607d8b")):
        into = np.flatnonzero(mv.kind == kind)
        into = into[into > 0]
        if len(into):
            fig.add_trace(_line3d(_segments(mv.tip[into - 1], mv.tip[into]), f"{prefix}{label}",
                                  line=dict(color=col, width=2, dash="dash"), hoverinfo="skip",
                                  visible=True if kind == 1 else "legendonly"))
    cut = np.flatnonzero(mv.kind == 0)
    every = max(1, int(np.ceil(len(cut) / 300)))
    at = cut[::every]
    if len(at):
        length = max(mv.diameter, 5.0)
        fig.add_trace(_line3d(_segments(mv.tip[at], mv.tip[at] + length * mv.axis[at]),
                              f"{prefix}tool axes (every {every} points)", hoverinfo="skip",
                              line=dict(color="#37474f", width=1.5),
                              visible=True if mv.multi_axis else "legendonly"))
    step = max(1, int(np.ceil(len(cut) / MARKER_BUDGET)))
    cl = mv.tip[cut[::step]]
    fig.add_trace(go.Scatter3d(x=cl[:, 0], y=cl[:, 1], z=cl[:, 2], mode="markers", visible="legendonly",
                               name=f"{prefix}CL points (tool tips){'' if step == 1 else f', every {step}'}",
                               marker=dict(size=2, color="#000000")))
    if cc is not None and len(cc):
        step_cc = max(1, int(np.ceil(len(cc) / MARKER_BUDGET)))
        c = cc[::step_cc]
        fig.add_trace(go.Scatter3d(x=c[:, 0], y=c[:, 1], z=c[:, 2], mode="markers", visible="legendonly",
                                   name=f"{prefix}CC points{'' if step_cc == 1 else f', every {step_cc}'}",
                                   marker=dict(size=2, color="#c62828")))
    return {"points": int(len(mv.tip)), "cut_points": int((mv.kind == 0).sum()),
            "drawn": int(keep.sum()), "tolerance": tol}


#: the 3D figures' legend: one row (wrapping) under the scene, outside it, so it covers no axis
#: (inside the scene's top left it lay over the Z axis, which this camera puts on the left)
LEGEND_BELOW = dict(orientation="h", x=0.0, xanchor="left", y=0.0, yanchor="top",
                    bgcolor="rgba(255,255,255,0.8)", font=dict(size=11))


def scene(title: str = "") -> dict:
    """A 3D scene with equal scales on X, Y and Z (mm)."""
    ax = dict(showbackground=True, backgroundcolor="#f5f5f5", gridcolor="#cfd8dc")
    return dict(aspectmode="data", xaxis=dict(title="X (mm)", **ax), yaxis=dict(title="Y (mm)", **ax),
                zaxis=dict(title="Z (mm)", **ax), camera=dict(eye=dict(x=-1.5, y=-1.8, z=1.3)))


def surface_trace(mesh: np.ndarray, name: str = "part", **kw):
    """The part as a grey surface from a (n, m, 3) grid of points."""
    import plotly.graph_objects as go

    return go.Surface(x=mesh[..., 0], y=mesh[..., 1], z=mesh[..., 2], name=name, showscale=False,
                      colorscale=[[0, "#b0bec5"], [1, "#eceff1"]], opacity=0.85, showlegend=True,
                      hoverinfo="skip", **kw)


def stl_trace(path: Path, max_faces: int = 60_000):
    """The part of an STL file (trimesh reads it) as a Mesh3d, every k-th face past ``max_faces``."""
    import plotly.graph_objects as go
    import trimesh

    mesh = trimesh.load(path, file_type="stl", force="mesh")
    faces = np.asarray(mesh.faces)
    faces = faces[:: max(1, int(np.ceil(len(faces) / max_faces)))]
    v = np.asarray(mesh.vertices)
    return go.Mesh3d(x=v[:, 0], y=v[:, 1], z=v[:, 2], i=faces[:, 0], j=faces[:, 1], k=faces[:, 2],
                     color="#b0bec5", opacity=0.8, name="part (surface.stl)", showlegend=True,
                     hoverinfo="skip", flatshading=False)


def toolpath_figure(moves: list[Moves], part=None, cc: np.ndarray | None = None, title: str = "",
                    name: str = "toolpath3d"):
    """(figure, caption): the part and the operations' moves in 3D, equal axis scales."""
    import plotly.graph_objects as go

    fig = go.Figure()
    if part is not None:
        fig.add_trace(part)
    stats = []
    for k, mv in enumerate(moves):
        prefix = f"{mv.name}: " if len(moves) > 1 else ""
        colour = None if len(moves) == 1 else OPERATION_HUE[k % len(OPERATION_HUE)]
        stats.append((mv.name, add_moves(fig, mv, prefix=prefix, cc=cc if k == len(moves) - 1 else None,
                                         colour=colour)))
    fig.update_layout(scene=scene(), height=720, margin=dict(l=0, r=0, t=40, b=0), title=title, meta=name,
                      legend=LEGEND_BELOW)
    caption = "; ".join(f"{n}: {s['cut_points']:,} cut points drawn as {s['drawn']:,} "
                        f"(decimated within {s['tolerance']:g} mm of the programmed path)" for n, s in stats)
    caption += (". Cuts coloured by zone (hue) and pass (shade) or by layer; links and rapids dashed "
                "(rapids off until clicked in the legend); CL and CC points on demand in the legend.")
    return fig, caption
