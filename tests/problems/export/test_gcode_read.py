"""G-code reader: our own ISO / Fanuc programs read back to the toolpath we wrote; arcs of
other systems within the chord tolerance; pygcode parses every line we write."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.export.gcode_read import GcodeError, read_gcode
from evoplan.problems.toolpath.export.kinematics import Kinematics, Rotary
from evoplan.problems.toolpath.export.posts import POSTS, Machine
from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath

KIN = Kinematics("table_table", Rotary("A", "x", (-30, 110)), Rotary("C", "z", (-360, 360)))


def paths():
    three = Toolpath("rough", Tool(1, make_cutter(12, 0), 6000), [[0, 0, 30], [0, 0, 11], [0, 0, 10], [50, 0, 9.5],
                                                     [50, 10, 9.5], [0, 10, 9], [0, 10, 30]],
                     np.tile([0, 0, 1.0], (7, 1)), [1, 1, 0, 0, 0, 0, 1], [0, 0, 1, 0, 0, 0, 0],
                     [-1, -1, 0, 0, 0, 0, -1], feed=800, plunge_feed=200)
    m = 60
    phi = np.linspace(0, 2.5, m)
    t = np.radians(25)
    axis = np.column_stack([np.sin(t) * np.cos(phi), np.sin(t) * np.sin(phi), np.full(m, np.cos(t))])
    x = np.linspace(0, 80, m)
    tip = np.column_stack([x, 5 * np.sin(x / 9), 2 * np.cos(x / 7)])
    five = Toolpath.from_passes("finish", Tool(3, make_cutter(12, 6), 9000), tip, axis, np.arange(m) // 20, feed=1200)
    return three, five


@pytest.mark.parametrize("name", ["iso", "fanuc"])
def test_our_programs_read_back_to_the_toolpath_we_wrote(tmp_path, name):
    three, five = paths()
    for tp in ([three] if name == "iso" else [three, five]):
        post = POSTS[name](Machine(KIN if post_five(name) else None, safe_z=60.0))
        f = tmp_path / f"{tp.name}.nc"
        f.write_text(post.program(tp))
        got = read_gcode(f, tp.tool.cutter, KIN if post_five(name) else None)
        want = post.moves(tp)
        # the moves as written: a block that changes nothing is not written
        keep = np.r_[True, np.abs(np.diff(np.c_[want.tip, np.nan_to_num(want.angles)], axis=0)).max(axis=1) > 1e-9]
        w_tip, w_rapid = want.tip[keep], want.rapid[keep]
        start = int(np.flatnonzero(np.abs(got.tip - w_tip[0]).max(axis=1) < 1e-4)[-1 if name == "iso" else 0])
        if name == "iso":   # the header's G43 Z move lands on the first point's Z: the first X Y block follows
            start = int(np.flatnonzero(np.abs(got.tip - w_tip[1]).max(axis=1) < 1e-4)[0]) - 1
        block = slice(start, start + len(w_tip))
        np.testing.assert_allclose(got.tip[block], w_tip, atol=6e-5)
        assert got.rapid[block][1:].tolist() == w_rapid[1:].tolist()
        if post_five(name):
            real = KIN.tool_axis(want.angles[keep, 0], want.angles[keep, 1])
            np.testing.assert_allclose(got.axis[block], real, atol=2e-6)
        assert got.ignored.get("M", 0) >= 3 and "S" in got.ignored


def post_five(name):
    return POSTS[name].five_axis


def test_arcs_of_other_systems_within_the_chord_tolerance(tmp_path):
    f = tmp_path / "other.nc"
    f.write_text("""%
O0001 (OTHER CAM)
N10 G21 G90 G17 G40 G49 G80
N20 T1 M6
N30 S8000 M3
N40 G0 X10. Y0. Z5.
N50 G1 Z-1. F300.
N60 G3 X0. Y10. I-10. J0. F1200.     (quarter, counter-clockwise)
N70 G2 X-10. Y0. R-10.                (three quarters clockwise, R < 0)
N80 G18 G2 X-20. Z-1. I-5. K0.       (a half circle in ZX)
N90 G91 G1 X5.
N100 G90 G0 Z50.
M30
%
""")
    tp = read_gcode(f, make_cutter(10.0, 0.0))
    assert tp.tip[0].tolist() == [10, 0, 5] and tp.tip[-1].tolist() == [-15, 0, 50] and tp.feed[1] == 300
    # the first arc: on the circle r = 10, angles rising from 0 to 90 deg
    q = tp.tip[2:]
    r = np.hypot(q[:, 0], q[:, 1])
    first = np.flatnonzero(np.isclose(q[:, 0], 0) & np.isclose(q[:, 1], 10))[0]
    np.testing.assert_allclose(r[:first + 1], 10, atol=1e-9)
    ang = np.arctan2(q[:first + 1, 1], q[:first + 1, 0])
    assert np.all(np.diff(ang) > 0)
    mids = 0.5 * (q[1:first + 1] + q[:first])
    assert (10 - np.hypot(mids[:, 0], mids[:, 1])).max() <= 0.01 + 1e-12
    # the R < 0 arc goes the long way (270 deg, clockwise) through (0, -10)
    second = np.flatnonzero(np.isclose(q[:, 0], -10) & np.isclose(q[:, 1], 0))[0]
    seg = q[first:second + 1]
    assert np.isclose(seg[:, 1].min(), -10, atol=0.05) and np.allclose(np.hypot(seg[:, 0], seg[:, 1]), 10)
    # the ZX half circle about (-15, 0, -1): below or above, always at r = 5 in ZX
    third = np.flatnonzero(np.isclose(q[:, 0], -20))[0]
    zx = q[second:third + 1][:, [0, 2]] - [-15, -1]
    np.testing.assert_allclose(np.hypot(zx[:, 0], zx[:, 1]), 5, atol=1e-9)
    assert tp.ignored["T"] == 1 and tp.ignored["N"] == 10 and not tp.multax


BAD = {
    "tilted plane arc": ("G90 G17\nG0 X0 Y0 Z0\nG68.2 X0 Y0 Z0 I0 J45 K0\nG2 X10 Y0 R5\n", 4, "tilted working plane"),
    "cycle": ("G90\nG0 X0 Y0 Z5\nG81 Z-5 R1 F100\n", 3, "canned cycle G81"),
    # read as the plane's parameters, the move to X20 was skipped without a word
    "move in a plane definition": ("G90 G17\nG0 X0 Y0 Z0\nG68 X0 Y0 R30 G1 X20\n", 3, "plane-definition block"),
    "arc off": ("G90\nG0 X10 Y0 Z0\nG3 X0 Y7 I-10 J0 F100\n", 3, "from its centre"),
    "rotary without kinematics": ("G90\nG0 X0 Y0 Z0 A10\n", 2, "rotary word A"),
    "garbage": ("G90\nG0 X0 Y0 Z0\nhello\n", 3, "not a G-code word"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_programs_name_their_line(tmp_path, case):
    text, line, words = BAD[case]
    (tmp_path / "bad.nc").write_text(text)
    with pytest.raises(GcodeError) as err:
        read_gcode(tmp_path / "bad.nc", make_cutter(10.0, 0.0))
    assert str(err.value).startswith(f"LINE {line}: ") and words in str(err.value)


def test_pygcode_parses_every_line_we_write():
    pygcode = pytest.importorskip("pygcode")
    three, five = paths()
    for name, tp in (("iso", three), ("fanuc", three), ("fanuc", five)):
        post = POSTS[name](Machine(KIN if POSTS[name].five_axis else None, safe_z=60.0))
        for line in post.program(tp).splitlines():
            if line.strip() in ("%", ""):
                continue
            pygcode.Line(line)   # raises on a word it cannot read


def test_simulate_measures_a_fanuc_program_as_the_plan(tmp_path, capsys):
    import json
    from pathlib import Path

    from evoplan.cli import main
    from evoplan.problems.toolpath.problem import ToolpathProblem

    run = Path(__file__).resolve().parents[3] / "runs" / "fountas_toolpath_vega.yaml"
    params = dict(tool=8, stepover=30.0, lead=1.0, tilt=0.5, step=8.0)
    pr = ToolpathProblem()
    path, _ = pr.cl_path(params)
    tp = Toolpath.from_sections("finish", Tool(8, make_cutter(12, 6), 9000), path.tip, path.axis, path.section, feed=1000)
    kin = Kinematics("table_table", Rotary("A", "x", (-120, 120)), Rotary("C", "z", (-1e6, 1e6)))
    (tmp_path / "f.nc").write_text(POSTS["fanuc"](Machine(kin, safe_z=60.0)).program(tp))
    sets = [a for k, v in params.items() for a in ("--set", f"{k}={v}")]
    assert main(["simulate", str(run), *sets, "--grid", "0.5", "--quiet", "--out", str(tmp_path / "a")]) == 0
    assert main(["simulate", str(run), "--nc", str(tmp_path / "f.nc"), "--tool", "12,6", "--grid", "0.5",
                 "--quiet", "--out", str(tmp_path / "b")]) == 0
    a, b = (json.loads((tmp_path / x / "simulation.json").read_text()) for x in "ab")
    # the words that do not move the tool, listed: the tool change, spindle, coolant, G43.4 ...
    ign = b["ignored_statements"]
    assert ign["T"] == 1 and ign["S"] == 1 and ign["G43.4"] == 1 and ign["G49"] >= 1 and ign["M"] >= 4
    for key in ("scallop_max_mm", "scallop_mean_mm", "gouge_max_mm", "uncut_fraction"):
        assert b[key] == pytest.approx(a[key], abs=3e-4), key
    capsys.readouterr()
    assert main(["simulate", str(run), "--nc", str(tmp_path / "f.nc"), "--tool", "0", "--out",
                 str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--tool" in err[0] and not (tmp_path / "c").exists()


@pytest.mark.parametrize("text,line,words", [
    # the P word of a G2 / G3 asks for extra full turns (a helix); reading the arc once would drop them
    ("G90 G17\nG0 X10 Y0 Z0\nG2 X10 Y0 I-10 J0 Z-6 P3 F300\n", 3, "P word"),
    ("G90 G17\nG0 X10 Y0 Z0\nG3 X0 Y10 I-10 F300\nX-10 Y0 P2\n", 4, "P word"),
    # a subprogram call runs motion the reader does not see
    ("G90\nG0 X0 Y0 Z5\nM98 P1234\n", 3, "M98"),
])
def test_words_that_change_motion_are_refused_with_their_line(tmp_path, text, line, words):
    (tmp_path / "p.nc").write_text(text)
    with pytest.raises(GcodeError) as err:
        read_gcode(tmp_path / "p.nc", make_cutter(10.0, 0.0))
    assert str(err.value).startswith(f"LINE {line}: ") and words in str(err.value), str(err.value)


def test_a_dwell_p_word_is_still_ignored(tmp_path):
    (tmp_path / "d.nc").write_text("G90 G17\nG0 X10 Y0 Z0\nG1 X0 F100\nG2 X-10 Y0 I-5 F100\nM3 S1000 P1\n")
    tp = read_gcode(tmp_path / "d.nc", make_cutter(10.0, 0.0))
    assert tp.ignored.get("P") == 1 and np.allclose(tp.tip[-1], [-10, 0, 0])
