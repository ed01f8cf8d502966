"""Post-processors: programs parse back to the same moves; 5-axis angles follow the kinematics."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.export.kinematics import Kinematics, ReachError, Rotary
from evoplan.problems.toolpath.export.posts import POSTS, Machine, PostError
from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath

LAYOUTS = [("table_table", "x"), ("table_table", "y"), ("head_table", "x"), ("head_table", "y")]


def kin(layout="table_table", about="x", tilt=(-110, 110), rotary=(-360, 360), max_step=10.0, **kw):
    return Kinematics(layout, Rotary("A" if about == "x" else "B", about, tilt), Rotary("C", "z", rotary), max_step,
                      **kw)


def cone_path(m=120, tilt_deg=25.0, turns=0.5):
    """Tool axes sweeping a cone around Z; tips along a wavy line; four passes."""
    phi = np.linspace(0, 2 * np.pi * turns, m)
    t = np.radians(tilt_deg)
    axis = np.column_stack([np.sin(t) * np.cos(phi), np.sin(t) * np.sin(phi), np.full(m, np.cos(t))])
    x = np.linspace(0, 80, m)
    tip = np.column_stack([x, 5 * np.sin(x / 9), 2 * np.cos(x / 7)])
    return Toolpath.from_passes("finish", Tool(8, make_cutter(12, 6), 9000), tip, axis, np.arange(m) * 4 // m, feed=1200)


@pytest.mark.parametrize("layout,about", LAYOUTS)
def test_rotary_angles_reproduce_the_axis(layout, about):
    k = kin(layout, about)
    rng = np.random.default_rng(3)
    t = rng.normal(size=(400, 3))
    t[:, 2] = np.abs(t[:, 2]) + 0.05
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    t[:3] = [[0, 0, 1], [0, 0, 1], [1e-14, 0, 1]]   # the pole
    ang, _ = k.angles(t)
    np.testing.assert_allclose(k.tool_axis(ang[:, 0], ang[:, 1]), t, atol=1e-9)


def test_no_flip_at_the_pole():
    # the axis tips over the pole in the XZ plane: the table holds still, the tilt changes sign
    a = np.radians(np.linspace(-20, 20, 81))
    axis = np.column_stack([np.sin(a), np.zeros_like(a), np.cos(a)])
    for layout, about in LAYOUTS:
        ang, unwind = kin(layout, about).angles(axis)
        assert np.ptp(ang[:, 1]) < 1e-9 and not unwind.any()
        assert np.abs(np.diff(ang[:, 0])).max() < 0.51


def test_limits_are_kept_and_unwinds_written():
    tp = cone_path(m=200, turns=2.0)           # two full turns of the table
    k = kin(rotary=(-200, 200))
    ang, unwind = k.angles(tp.axis)
    assert ang[:, 1].min() >= -200 and ang[:, 1].max() <= 200 and ang[:, 0].min() >= -110
    assert unwind.sum() >= 1
    post = POSTS["fanuc"](Machine(k))
    back = post.read(post.program(tp))
    # a jump above the threshold only across rapids (retract, turn, re-approach)
    jump = np.abs(np.diff(back.angles, axis=0)).max(axis=1)
    big = np.flatnonzero(jump > k.max_step + 1e-3) + 1
    assert len(big) >= 1 and back.rapid[big].all()
    assert back.angles[:, 1].min() >= -200 and back.angles[:, 1].max() <= 200


def test_large_turns_split_at_small_tilt_and_reposition_at_large_tilt():
    k = kin(max_step=5.0, rotary_threshold=90.0)   # turns up to 90 degrees allowed while cutting
    for tilt, repositions in ((2.0, 0), (30.0, 1)):
        t, phi = np.radians(tilt), np.radians([0.0, 0.0, 120.0, 120.0])
        axis = np.column_stack([np.sin(t) * np.cos(phi), np.sin(t) * np.sin(phi), np.full(4, np.cos(t))])
        tp = Toolpath("f", Tool(1, make_cutter(10, 5)), [[0, 0, 10], [0, 0, 0], [3, 0, 0], [6, 0, 0]], axis,
                      [1, 0, 0, 0], [0, 1, 0, 0], [-1, 0, 0, 0], feed=1000, plunge_feed=200)
        _, unwind = k.angles(axis)
        assert unwind.sum() == repositions
        post = POSTS["siemens"](Machine(k))
        back = post.read(post.program(tp))
        cut = ~back.rapid[1:]
        assert np.abs(np.diff(back.angles, axis=0)).max(axis=1)[cut].max() <= 5.0 + 1e-3
        if repositions == 0:   # the 120 degree azimuth change: the other tilt branch turns C by 60
            # steps; rapids: rotaries, over the start at the clearance, approach, retract (2)
            assert cut.sum() == 1 + 12 + 1 and back.rapid.sum() == 5


def test_unreachable_axis_names_the_point():
    axis = cone_path(tilt_deg=20.0).axis
    kin(tilt=(-30, 30)).angles(axis)
    axis[7] = [np.sin(0.7), 0, np.cos(0.7)]     # 40 degrees
    with pytest.raises(ReachError, match=r"^point 7: tool axis \(0.644218, 0.000000, 0.764842\) is out of reach "
                                         r"of A in \[-30, 30\]"):
        kin(tilt=(-30, 30)).angles(axis)


@pytest.mark.parametrize("name", sorted(POSTS))
def test_every_line_parses_back_to_the_moves(name):
    three = Toolpath("rough", Tool(1, make_cutter(12, 0), 6000), [[0, 0, 30], [0, 0, 11], [0, 0, 10], [50, 0, 9.5], [50, 10, 9.5],
                                                     [0, 10, 9], [0, 10, 30]],
                     np.tile([0, 0, 1.0], (7, 1)), [1, 1, 0, 0, 0, 0, 1], [0, 0, 1, 0, 0, 0, 0],
                     [-1, -1, 0, 0, 0, 0, -1], feed=800, plunge_feed=200)
    cases = [three] if name == "iso" else [three, cone_path(turns=1.5)]
    for tp in cases:
        post = POSTS[name](Machine(None if name == "iso" else kin()))
        text = post.program(tp, "op")
        back, want = post.read(text), post.moves(tp)
        first = int(np.flatnonzero(~np.isnan(back.tip[:, :2]).any(axis=1))[0])   # after the header moves
        got = back.tip[first:first + len(want.tip)]
        np.testing.assert_allclose(got, want.tip, atol=6e-5)
        assert back.rapid[first:first + len(want.tip)].tolist() == want.rapid.tolist()
        np.testing.assert_allclose(back.feed[first:first + len(want.tip)], want.feed, atol=0.06)
        if post.five_axis:
            np.testing.assert_allclose(back.angles[first:first + len(want.tip)], want.angles, atol=6e-5)
    with pytest.raises(ValueError, match="line 2"):
        post.read(text.replace("\n", "\nQ5 FOO\n", 1))


def test_iso_refuses_tilted_axes():
    with pytest.raises(PostError, match="3-axis"):
        POSTS["iso"](Machine()).program(cone_path())


LONG = ("finish: torus D12 r2 (tool 6), step-over 41.729 % of D, lead 2.957 deg, tilt 0.027 deg, "
        "step 6.338 mm, zones 3, scallop max 0.106 mm")


@pytest.mark.parametrize("name", ["iso", "fanuc"])
def test_long_comments_are_split_between_words_not_cut(name):
    m = 40
    x = np.linspace(0, 60, m)
    tip = np.column_stack([x, np.zeros(m), np.sin(x / 9)])
    axis = cone_path(m=m).axis[1:-1] if name == "fanuc" else np.tile([0.0, 0.0, 1.0], (m, 1))
    tp = Toolpath.from_passes("finish", Tool(8, make_cutter(12, 6), 9000), tip, axis, np.arange(m) * 2 // m,
                              feed=1200, comments=[LONG])
    post = POSTS[name](Machine(kin()) if POSTS[name].five_axis else Machine())
    program = post.program(tp).splitlines()
    assert max(map(len, program)) <= 72
    comments = [line[1:-1] for line in program if line.startswith("(") and line.endswith(")")]
    assert " ".join(LONG.upper().replace("(", "[").replace(")", "]").split()) in " ".join(comments)


def test_long_apt_comments_are_split_between_words_not_cut():
    from evoplan.problems.toolpath.export.apt_write import header

    lines = header(cutter=make_cutter(12, 2), comments=[LONG, "short"])
    assert max(map(len, lines)) <= 72
    comments = [line[3:] for line in lines if line.startswith("$$ ") and "TOOLPOINT" not in line]
    assert " ".join(comments) == LONG + " short"
