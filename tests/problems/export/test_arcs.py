"""Point reduction and arc fitting of NC programs: every point of the path within the chord
tolerance of what is written, arcs read back by the posts' grammar, the G-code reader,
``simulate --nc`` and pygcode."""

from __future__ import annotations

import re

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.export.arcs import PLANES, arc_points, fit_blocks, segment_distance
from evoplan.problems.toolpath.export.gcode_read import read_gcode
from evoplan.problems.toolpath.export.kinematics import Kinematics, Rotary
from evoplan.problems.toolpath.export.posts import POSTS, Machine
from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath, drop_collinear

TOL = 0.01


def _blocks_as_points(P, blocks, step=1e-3):
    """The written path (lines and arcs) as a dense polyline."""
    out = [P[0]]
    start = 0
    for end, motion, plane, centre in zip(blocks.end, blocks.motion, blocks.plane, blocks.centre):
        if motion >= 2:
            out += list(arc_points(P[start], P[end], centre, plane, motion == 2, step))
        out.append(P[end])
        start = end
    return np.array(out)


def _polyline_distance(points, poly):
    """Distance of each of ``points`` to the polyline ``poly``."""
    return np.min([segment_distance(points, poly[k], poly[k + 1]) for k in range(len(poly) - 1)], axis=0)


def _curve(plane, n=120, noise=0.0, seed=0):
    """A polyline in ``plane``: a circle of radius 25 over 200 degrees, a straight run, a circle
    of radius 8 the other way round, sampled at chord error < TOL / 2, points moved in plane
    by up to ``noise``."""
    rng = np.random.default_rng(seed)
    t1 = np.linspace(0, np.radians(200), n)
    first = np.column_stack([25 * np.cos(t1), 25 * np.sin(t1)])
    line = first[-1] + np.linspace(0, 1, 30)[1:, None] * np.array([0.0, -30.0])
    c2 = line[-1] + [8.0 * np.cos(np.radians(20)), -8.0 * np.sin(np.radians(20))]  # tangent-ish join
    t2 = np.linspace(np.pi + np.radians(20), np.radians(-60), 80)
    second = c2 + 8 * np.column_stack([np.cos(t2), np.sin(t2)])
    q = np.vstack([first, line, second])
    q = q + rng.uniform(-noise, noise, q.shape)
    a, b, c = PLANES[plane]
    P = np.zeros((len(q), 3))
    P[:, a], P[:, b], P[:, c] = q[:, 0], q[:, 1], 4.25
    return P


@pytest.mark.parametrize("plane", ["17", "18", "19"])
def test_fitted_arcs_keep_every_point_within_the_tolerance(plane):
    P = _curve(plane, noise=0.3 * TOL)
    blocks = fit_blocks(P, TOL)
    arcs = blocks.motion >= 2
    assert arcs.sum() >= 2 and {blocks.plane[k] for k in np.flatnonzero(arcs)} == {plane}
    assert len(blocks.end) < len(P) / 10  # a curve of 230 points in a handful of blocks
    written = _blocks_as_points(P, blocks)
    # every original point within TOL of the written path, and every written point within
    # TOL of the original polyline (densely sampled arcs: 1e-3 chord error)
    assert _polyline_distance(P, written).max() <= TOL + 1e-3
    assert _polyline_distance(written, P).max() <= TOL + 1e-9
    # the normal coordinate never moves
    assert np.ptp(written[:, PLANES[plane][2]]) == 0
    # and the check is real: a tolerance below the noise fits far fewer points per block
    tight = fit_blocks(P, 0.1 * TOL)
    assert len(tight.end) > 2 * len(blocks.end)
    assert _polyline_distance(P, _blocks_as_points(P, tight)).max() <= 0.1 * TOL + 1e-3


def test_lines_merge_near_collinear_points_but_keep_a_reversal():
    rng = np.random.default_rng(1)
    x = np.linspace(0, 40, 81)
    P = np.column_stack([x, 0.4 * TOL * rng.uniform(-1, 1, 81), np.zeros(81)])
    blocks = fit_blocks(P, TOL, arcs=False)
    assert blocks.end.tolist() == [80] and (blocks.motion == 1).all()
    noisy = P.copy()
    noisy[:, 1] *= 5  # +-2 TOL: more blocks, every dropped point within TOL of its block's segment
    b = fit_blocks(noisy, TOL, arcs=False)
    assert len(b.end) > 3
    starts = np.r_[0, b.end[:-1]]
    for s, e in zip(starts, b.end):
        if e - s > 1:
            assert segment_distance(noisy[s + 1:e], noisy[s], noisy[e]).max() <= TOL
    there_and_back = np.array([[0, 0, 0], [10, 0, 0], [20, 0, 0], [5, 0, 0.0]])
    assert fit_blocks(there_and_back, TOL).end.tolist() == [2, 3]  # the turn at x = 20 is kept


def test_roughing_thinning_keeps_a_reversal_along_a_line():
    # the roughing builders' thinning measured the distance to the chord's line: the turn at
    # x = 20 of a there-and-back move lay on that line and was dropped (the path 0 -> 5)
    there_and_back = np.array([[0, 0, 0], [10, 0, 0], [20, 0, 0], [5, 0, 0.0]])
    assert drop_collinear(there_and_back, TOL).tolist() == [True, False, True, True]
    rng = np.random.default_rng(2)
    x = np.r_[np.linspace(0, 30, 61), np.linspace(29.5, 12, 36)]  # out along X and back
    P = np.column_stack([x, 2 * TOL * rng.uniform(-1, 1, len(x)), np.zeros(len(x))])
    keep = np.flatnonzero(drop_collinear(P, TOL))
    assert keep[0] == 0 and keep[-1] == len(P) - 1 and P[keep, 0].max() >= 29.9  # the far end stays
    for s, e in zip(keep[:-1], keep[1:]):
        if e - s > 1:
            assert segment_distance(P[s + 1:e], P[s], P[e]).max() <= TOL


def _toolpath():
    """A 3-axis toolpath: an approach, the G17 curve at z 4.25, a G18 curve, a retract."""
    xy = _curve("17")
    xz = _curve("18", n=60)
    xz[:, 1] = -40.0
    xz[:, 0] += 60.0
    tip = np.vstack([[xy[0, 0], xy[0, 1], 30.0], xy, [xy[-1, 0], xy[-1, 1], 30.0], [xz[0, 0], -40.0, 30.0],
                     xz, [xz[-1, 0], -40.0, 40.0]])
    m = len(tip)
    rapid = np.zeros(m, bool)
    rapid[[0, len(xy) + 1, len(xy) + 2, m - 1]] = True
    plunge = np.zeros(m, bool)
    plunge[[1, len(xy) + 3]] = True
    section = np.r_[-1, np.zeros(len(xy), int), -1, -1, np.ones(len(xz), int), -1]
    return Toolpath("rough", Tool(1, make_cutter(12, 0), 6000), tip, np.tile([0, 0, 1.0], (m, 1)), rapid, plunge, section,
                    feed=800, plunge_feed=250)


def _kinematics():
    return Kinematics("table_table", Rotary("A", "x", (-30, 110)), Rotary("C", "z", (-360, 360)), 10.0)


ARC_DIALECTS = sorted(name for name, cls in POSTS.items() if cls.arcs)
# how each dialect writes an arc (the plane's own word where it has one)
ARC_LINE = {"iso": r"(G1[789] )?G[23] ", "fanuc": r"(G1[789] )?G[23] ", "siemens": r"(G1[789] )?G[23] ",
            "heidenhain": r"\d+ C [XYZ][+-][\d.]+ [XYZ][+-][\d.]+ DR[+-]"}


def test_every_dialect_with_circular_interpolation_writes_arcs():
    # the four shipped dialects have circular interpolation; a new one with arcs needs its line form here
    assert {"fanuc", "heidenhain", "iso", "siemens"} <= set(ARC_DIALECTS) <= set(ARC_LINE)


@pytest.mark.parametrize("name", ARC_DIALECTS)
def test_arcs_read_back_within_the_tolerance_in_every_dialect(name, tmp_path):
    tp = _toolpath()
    k = _kinematics() if POSTS[name].five_axis else None
    plain = POSTS[name](Machine(k)).program(tp)
    post = POSTS[name](Machine(k, tolerance=TOL))
    text = post.program(tp)
    arc_lines = [line for line in text.splitlines() if re.match(ARC_LINE[name], line)]
    assert len(arc_lines) >= 4
    if name == "heidenhain":  # the centre before its arcs, in the plane the arc's words name
        assert re.search(r"CC X[+-][\d.]+ Z[+-][\d.]+\n\d+ C X[+-][\d.]+ Z[+-][\d.]+ DR[+-]", text)
        assert not re.search(r"\bG[23]\b|\bI[+-]?\d", text)
    else:
        assert "G18 G" in text and "G17 G" in text  # the plane changes and back
    assert len(text) < 0.35 * len(plain)
    cut = ~tp.rapid
    (tmp_path / "p.nc").write_text(text)
    readers = [post.read(text).tip]
    if name in ("iso", "fanuc"):  # the ISO/Fanuc G-code reader takes these dialects
        readers.append(read_gcode(tmp_path / "p.nc", make_cutter(12, 0), k).tip)
    for got in readers:
        got = got[np.isfinite(got).all(axis=1)]  # the header's Z move has no X Y yet
        # every cutting point of the toolpath within TOL of the program read back, and back
        assert _polyline_distance(tp.tip[cut], got).max() <= TOL + 2e-3
        inside = got[(got[:, 2] < 5) & (got[:, 1] > -39)]  # the G17 curve's points as read
        assert _polyline_distance(inside, tp.tip[1:len(_curve("17")) + 1]).max() <= TOL + 1e-4
    feeds = post.read(text).feed
    assert set(np.unique(feeds[np.isfinite(feeds)])) == {250.0, 800.0}  # cutting at 800, plunges at 250
    if name in ("iso", "fanuc"):
        g = read_gcode(tmp_path / "p.nc", make_cutter(12, 0), k)
        assert set(np.unique(g.feed[~g.rapid])) == {250.0, 800.0}


def test_arcs_only_where_the_rotaries_hold_still():
    # a 5-axis finish whose rotaries move: linear blocks only, even with a tolerance (G43.4
    # circular interpolation needs the table axes held, FANUC A-79348E)
    m = 60
    phi = np.linspace(0, np.pi, m)
    axis = np.column_stack([0.3 * np.cos(phi), 0.3 * np.sin(phi), np.full(m, np.sqrt(1 - 0.09))])
    t = np.linspace(0, np.pi, m)
    tip = np.column_stack([20 * np.cos(t), 20 * np.sin(t), np.zeros(m)])  # a circle a fit would take
    tool = Tool(3, make_cutter(12, 6), 9000)
    turning = Toolpath.from_passes("f", tool, tip, axis, np.zeros(m, int), feed=1000)
    held = Toolpath.from_passes("f", tool, tip, np.tile([0, 0, 1.0], (m, 1)), np.zeros(m, int), feed=1000)
    for name in ("fanuc", "heidenhain", "siemens"):
        post = POSTS[name](Machine(_kinematics(), tolerance=TOL))
        assert not any(re.match(ARC_LINE[name], line) for line in post.program(turning).splitlines()), name
        assert any(re.match(ARC_LINE[name], line) for line in post.program(held).splitlines()), name


@pytest.mark.parametrize("text,message", [
    ("0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 C X+1 Y+1 DR+\n", "before any circle centre CC"),
    ("0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 CC X+1 Z+0\n3 C X+2 Y+0 DR+\n", "C in XY, the centre CC in XZ"),
    ("0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 CC X+1 Y+0\n3 C X+5 Y+0 DR+\n", "not the radius"),
    ("0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 CC X+1 Y+0\n3 C X+2 Y+0 DR\n", "not a C X.. Y.. DR+/-"),
])
def test_heidenhain_reader_refuses_a_bad_circle(text, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        POSTS["heidenhain"](Machine(_kinematics())).read(text)


@pytest.mark.parametrize("name", ["iso", "fanuc"])
def test_pygcode_parses_every_arc_line(name):
    pygcode = pytest.importorskip("pygcode")
    k = _kinematics() if POSTS[name].five_axis else None
    text = POSTS[name](Machine(k, tolerance=TOL)).program(_toolpath())
    arcs = 0
    for line in text.splitlines():
        if line.strip() in ("%", ""):
            continue
        parsed = pygcode.Line(line)
        arcs += any(type(g).__name__.startswith("GCodeArcMove") for g in parsed.block.gcodes)
    assert arcs >= 4


def test_simulate_nc_reads_the_arcs(tmp_path, capsys):
    import json
    from pathlib import Path

    from evoplan.cli import main

    run = Path(__file__).resolve().parents[3] / "runs" / "fountas_toolpath_vega.yaml"
    tp = _toolpath()
    tp.tip[:, :2] = tp.tip[:, :2] * 0.8 + [-47.0, -52.0]  # over the Fountas part (z 3.6 .. 49.8)
    tp.tip[:, 2] += 20.75  # the G17 curve at z 25 cuts into it, the G18 curve passes over it
    tp.tip[tp.section == 1, 2] += 60.0
    (tmp_path / "a.nc").write_text(POSTS["iso"](Machine(tolerance=TOL)).program(tp))
    (tmp_path / "b.nc").write_text(POSTS["iso"](Machine()).program(tp))
    out = {}
    for k in "ab":
        assert main(["simulate", str(run), "--nc", str(tmp_path / f"{k}.nc"), "--tool", "12", "--grid", "1",
                     "--quiet", "--out", str(tmp_path / k)]) == 0
        out[k] = json.loads((tmp_path / k / "simulation.json").read_text())
    capsys.readouterr()
    assert out["b"]["gouge_max_mm"] > 1.0  # the curve does cut
    for key in ("gouge_max_mm", "uncut_fraction"):
        # the reduced program lies within TOL of the plan and simulate reads its arcs at 1 um
        assert out["a"][key] == pytest.approx(out["b"][key], abs=TOL + 2e-3), key
    blocks = sum(line.startswith(("G1", "G2", "G3", "X", "Y", "Z")) for line in (tmp_path / "a.nc").read_text().splitlines())
    assert out["a"]["cl_points"] > blocks  # the arcs were read as points, not as their end points
