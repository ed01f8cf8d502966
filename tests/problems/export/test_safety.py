"""Safety of 5-axis programs, checked on the text read back: rotary turns above the threshold
only at the clearance plane, the program ends there before TCP is cancelled, the table holds
near the pole (and a ball keeps its centre there)."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.export.kinematics import Kinematics, Rotary
from evoplan.problems.toolpath.export.posts import POSTS, Machine
from evoplan.problems.toolpath.export.safety import check_program
from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath

SAFE = 40.0
FIVE = [n for n in sorted(POSTS) if POSTS[n].five_axis]


def kin(**kw):
    return Kinematics("table_table", Rotary("A", "x", (-30, 110)), Rotary("C", "z", (-360, 360)), **kw)


def wild_path(m=90):
    """Tool axes jumping between tilts of 5..60 deg and azimuths all round: large axis changes."""
    rng = np.random.default_rng(7)
    tilt = np.radians(np.repeat(rng.uniform(5, 60, m // 6), 6))
    phi = np.radians(np.repeat(rng.uniform(-180, 180, m // 6), 6))
    axis = np.column_stack([np.sin(tilt) * np.cos(phi), np.sin(tilt) * np.sin(phi), np.cos(tilt)])
    x = np.linspace(0, 80, m)
    tip = np.column_stack([x, 5 * np.sin(x / 9), 2 * np.cos(x / 7)])
    return Toolpath.from_passes("finish", Tool(3, make_cutter(12, 6), 9000), tip, axis, np.arange(m) // 6, feed=1200)


@pytest.mark.parametrize("name", FIVE)
def test_large_axis_changes_pass_the_check(name):
    post = POSTS[name](Machine(kin(), safe_z=SAFE))
    text = post.program(wild_path())
    rep = check_program(post, text, SAFE)
    assert rep.ok, rep.violations
    assert rep.repositions >= 10          # the jumps are made, at the clearance plane
    moves = post.read(text)
    turn = np.abs(np.diff(moves.angles, axis=0)).max(axis=1)
    big = np.flatnonzero(turn > 20 + 1e-3)
    assert len(big) and (moves.tip[big, 2] >= SAFE - 1e-3).all() and (moves.tip[big + 1, 2] >= SAFE - 1e-3).all()


def test_a_program_broken_on_purpose_fails():
    post = POSTS["fanuc"](Machine(kin(), safe_z=SAFE))
    lines = post.program(wild_path()).splitlines()
    g49 = lines.index("G49")
    # 1. the retract before G49 removed: TCP cancelled next to the part
    no_retract = "\n".join(lines[:g49 - 2] + lines[g49:])
    assert any("TCP is cancelled at Z" in v for v in check_program(post, no_retract, SAFE).violations)
    # 2. a turn at the clearance plane moved down to Z 5
    moves = post.read("\n".join(lines))
    turn = np.abs(np.diff(moves.angles, axis=0)).max(axis=1)
    i = int(np.flatnonzero(turn > 20)[0])
    z = f"Z{SAFE:g}."
    at = [k for k, line in enumerate(lines) if z in line]
    low = list(lines)
    for k in at:
        low[k] = low[k].replace(z, "Z5.")
    rep = check_program(post, "\n".join(low), SAFE)
    assert any("rotaries turn by" in v for v in rep.violations), (i, rep.violations)
    # 3. the same check in a higher plane than the program's fails everywhere it turns
    assert not check_program(post, "\n".join(lines), SAFE + 50).ok


def test_table_holds_near_the_pole_and_the_ball_keeps_its_centre():
    # a pass across the pole, 0.3 deg off it: the exact azimuth swings by 180 deg
    m = 41
    y = np.linspace(-1, 1, m)
    t = np.radians(0.3)
    axis = np.column_stack([np.full(m, np.sin(t)), y * 0.02, np.ones(m)])
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    tip = np.column_stack([np.zeros(m), 20 * y, np.zeros(m)])
    tp = Toolpath.from_passes("f", Tool(3, make_cutter(12, 6), 9000), tip, axis, np.zeros(m, int), feed=1000)
    exact = POSTS["fanuc"](Machine(kin(pole_angle=0.0), safe_z=SAFE))
    held = POSTS["fanuc"](Machine(kin(pole_angle=2.0), safe_z=SAFE))
    e, h = (p.read(p.program(tp)) for p in (exact, held))
    cut = ~h.rapid
    assert np.ptp(h.angles[cut, 1]) < 1e-9 < 20 < np.ptp(e.angles[~e.rapid, 1])
    assert check_program(held, held.program(tp), SAFE).ok
    # the ball's centre (tip + r * axis as the machine holds it) is the planned one
    k = held.machine.kinematics
    real = k.tool_axis(h.angles[cut, 0], h.angles[cut, 1])
    np.testing.assert_allclose(h.tip[cut] + 6 * real, tp.tip[1:-1] + 6 * tp.axis[1:-1], atol=2e-4)
    assert 0 < held.axis_error < 2.0


@pytest.mark.parametrize("key,value", [("rotary_threshold", 0), ("rapid_rotary", -1), ("pole_angle", 95)])
def test_bad_safety_settings_name_their_key(key, value):
    with pytest.raises(ValueError, match=f"^{key}: must be"):
        kin(**{key: value})


@pytest.mark.parametrize("name,cancel", [("fanuc", "G49"), ("siemens", "TRAFOOF")])
def test_a_move_down_after_tcp_is_cancelled_fails(name, cancel):
    post = POSTS[name](Machine(kin(), safe_z=SAFE))
    lines = post.program(wild_path()).splitlines()
    k = lines.index(cancel)
    assert check_program(post, "\n".join(lines), SAFE).ok
    down = "\n".join(lines[:k + 1] + ["G0 Z5."] + lines[k + 1:])
    assert any("after TCP is cancelled a move goes down to Z 5.000" in v
               for v in check_program(post, down, SAFE).violations)


FANUC_HEAD = ["%", "O1000", "G21 G90 G17 G40 G49 G80", "T3 M6", "S9000 M3", "M8", "G54",
              "G0 A30. C0.", "G43.4 H3", "G0 X0. Y0. Z40.", "G0 Z5."]
FANUC_TAIL = ["G0 Z40.", "G49", "M9", "M5", "M30", "%"]


def test_a_turn_split_into_small_rapid_blocks_below_the_clearance_fails():
    post = POSTS["fanuc"](Machine(kin(), safe_z=SAFE))
    one = FANUC_HEAD + ["G0 C60."] + FANUC_TAIL
    assert any("rotaries turn by 60.00 deg at Z 5.000" in v for v in check_program(post, "\n".join(one), SAFE).violations)
    # the same 60 deg as six rapid blocks of 10 deg: still a turn next to the part
    six = FANUC_HEAD + [f"G0 C{10 * k}." for k in range(1, 7)] + FANUC_TAIL
    rep = check_program(post, "\n".join(six), SAFE)
    assert any("rotaries turn by 60.00 deg in 6 non-cutting blocks at Z 5.000" in v for v in rep.violations), rep.violations
    # feed blocks that stay in place are non-cutting too
    slow = FANUC_HEAD + ["G1 F500."] + [f"C{10 * k}." for k in range(1, 7)] + FANUC_TAIL
    assert any("in 6 non-cutting blocks" in v for v in check_program(post, "\n".join(slow), SAFE).violations)
    # A and C each under the threshold: each axis is summed on its own (15 + 15 deg, 3 blocks each)
    both = FANUC_HEAD + ["G0 A35. C5.", "G0 A40. C10.", "G0 A45. C15."] + FANUC_TAIL
    assert check_program(post, "\n".join(both), SAFE).ok
    # the turns rise to the clearance between the steps: allowed
    up = FANUC_HEAD + [f"G0 Z40.\nC{10 * k}.\nZ5." for k in range(1, 7)] + FANUC_TAIL
    assert check_program(post, "\n".join(up), SAFE).ok
    # 5-axis finishing turns while it cuts: feed blocks that move the tip are not summed
    cut = FANUC_HEAD + ["G1 F500."] + [f"X{k}. C{10 * k}." for k in range(1, 13)] + FANUC_TAIL
    assert check_program(post, "\n".join(cut), SAFE).ok
    # ... and a cutting block between rapids ends the run
    split = FANUC_HEAD + ["G0 C10.", "C20.", "G1 X1. F500.", "G0 C30.", "C40."] + FANUC_TAIL
    assert check_program(post, "\n".join(split), SAFE).ok
