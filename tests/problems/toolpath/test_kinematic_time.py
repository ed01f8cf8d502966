"""Kinematic machining time: the S-curve feed profile against its closed forms."""

import math

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.criteria.kinematic_time import Dynamics, chain_time
from evoplan.problems.toolpath.spec import ToolpathSpec

DYN = Dynamics()                  # jerk 40 m/s^3, accel 6 m/s^2, feed 5 m/min
F = 5000.0 / 60.0                 # mm/s
A, J = 6000.0, 40000.0


def t_change(dv):
    """Closed form of the S-curve speed change (A^2 / J = 900 mm/s > F: jerk-limited)."""
    return dv / A + A / J if dv >= A * A / J else 2 * math.sqrt(dv / J)


def test_straight_line_is_its_closed_form():
    for length in (50.0, 300.0):
        pts = np.array([[0, 0, 0], [length, 0, 0.0]])
        got = chain_time(pts, 5000.0, DYN).sum()
        assert got == pytest.approx(length / F + t_change(F), rel=1e-9)
    # too short to reach the feed: peak v with 2 D(0, v) = L, i.e. v = (L^2 J / 4)^(1/3) ...
    length = 0.5
    vp = (length / 2) ** (2 / 3) * J ** (1 / 3)          # D(0, v) = v sqrt(v / J) = L / 2
    assert vp < F
    got = chain_time(np.array([[0, 0, 0], [length, 0, 0.0]]), 5000.0, DYN).sum()
    assert got == pytest.approx(2 * t_change(vp), rel=1e-6)
    # the acceleration-limited regime (A^2 / J below F)
    slow = Dynamics(accel=0.5, jerk=40.0)
    a = 500.0
    got = chain_time(np.array([[0, 0, 0], [300.0, 0, 0]]), 5000.0, slow).sum()
    assert got == pytest.approx(300 / F + F / a + a / J, rel=1e-9)


@pytest.mark.parametrize("n", [1, 2, 5, 9])
def test_zigzag_of_n_passes_costs_n_reversals(n):
    # n passes of 120 mm back and forth along X: every reversal is a full stop
    xs = [0.0, 120.0] * ((n + 2) // 2)
    pts = np.array([[x, 0.0, 0.0] for x in xs[:n + 1]])
    got = chain_time(pts, 5000.0, DYN).sum()
    penalty = t_change(F)                                   # decelerate + accelerate - the cruise
    assert got == pytest.approx(n * 120.0 / F + n * penalty, rel=1e-9)


def test_infinite_acceleration_is_length_over_feed():
    rng = np.random.default_rng(2)
    pts = np.cumsum(rng.normal(size=(200, 3)), axis=0)
    length = np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()
    fast = Dynamics(accel=1e12, jerk=1e15)
    assert chain_time(pts, 5000.0, fast).sum() == pytest.approx(length / F, rel=1e-6)
    # with the real limits the same path takes longer: its corners slow it down
    assert chain_time(pts, 5000.0, DYN).sum() > 1.2 * length / F


def test_gentle_points_cost_nothing_and_sharp_corners_slow_down():
    t = np.linspace(0, np.pi, 400)
    arc = np.column_stack([20 * np.cos(t), 20 * np.sin(t), 0 * t])
    length = np.linalg.norm(np.diff(arc, axis=0), axis=1).sum()
    # 399 blocks whose corners (0.45 deg) never limit the speed: one S-curve, the line's closed form
    assert chain_time(arc, 5000.0, DYN).sum() == pytest.approx(length / F + t_change(F), rel=1e-9)
    # a square's 90 degree corners: v_c^2 = A delta s / (1 - s), s = sin 45 deg
    s = math.sin(math.pi / 4)
    vc = math.sqrt(A * 0.01 * s / (1 - s))
    square = np.array([[0, 0, 0], [40, 0, 0], [40, 40, 0], [0, 40, 0.0]])
    got = chain_time(square, 5000.0, DYN).sum()
    # each corner: decelerate F -> vc and accelerate back; the time lost vs cruising is
    # 2 (T - D / F) with T = T(F - vc), D = (F + vc) / 2 T
    T = t_change(F - vc)
    lost = 2 * (T - (F + vc) / 2 * T / F)
    assert got == pytest.approx(120 / F + t_change(F) + 2 * lost, rel=1e-9)


@pytest.mark.parametrize("key,value", [("accel", 0), ("jerk", -1), ("feed", "fast")])
def test_bad_limits_name_their_key(key, value):
    with pytest.raises(ValueError, match=f"^dynamics.{key}: "):
        ToolpathSpec.from_params({"dynamics": {key: value}})


def test_the_criterion_on_plans_limits_to_the_nominal_and_is_weightable():
    from evoplan.problems.toolpath import ToolpathProblem
    from evoplan.problems.toolpath.criteria.table import check_name

    assert check_name("machining_time", "weights", weightable=True) == "machining_time"
    assert check_name("machining_time_nominal", "weights", weightable=True) == "machining_time_nominal"
    kw = dict(weights={"cc_count": 1.0}, normalization={"cc_count": [0, 1]}, feed_rate=1000.0)
    ideal = ToolpathProblem(dynamics={"accel": 1e12, "jerk": 1e15, "feed": 1000.0}, **kw)
    real = ToolpathProblem(**kw)
    X = ideal.genes.design(6, 3)
    a, b = ideal.criteria(X), real.criteria(X)
    np.testing.assert_allclose(a["machining_time"], a["machining_time_nominal"], rtol=1e-6)
    # the real limits at the programmed feed (feed_rate 1000): corners, starts and stops cost
    # time, so the plan runs slower than its length over that feed
    assert np.all(b["machining_time"] > b["machining_time_nominal"])
    np.testing.assert_allclose(b["machining_time_nominal"], b["path_length"] / 1000.0, rtol=1e-12)


def test_a_tool_library_feed_drives_the_time_and_an_entry_without_one_is_refused():
    from evoplan.problems.toolpath import ToolpathProblem
    from evoplan.problems.toolpath.tools import DEFAULT_TOOLS

    tools = [dict(t) for t in DEFAULT_TOOLS]
    kw = dict(weights={"cc_count": 1.0}, normalization={"cc_count": [0, 1]},
              dynamics={"accel": 1e12, "jerk": 1e15})
    slow = ToolpathProblem(tools=[{**t, "feed": 2500.0, "spindle": 8000} for t in tools], **kw)
    X = slow.genes.design(3, 1)
    c = slow.criteria(X)
    np.testing.assert_allclose(c["machining_time"], c["path_length"] / 2500.0, rtol=1e-6)
    # the length-based time at the same feed (it took feed_rate, 1000, whatever the library said)
    np.testing.assert_allclose(c["machining_time_nominal"], c["path_length"] / 2500.0, rtol=1e-12)
    # the plan's APT program carries the same feed (it carried feed_rate, 1000)
    apt = slow.artifacts(X[0])["toolpath.apt"].decode()
    assert "FEDRAT/2500.0000" in apt and "FEDRAT/1000" not in apt
    tools[2]["spindle"] = 9000
    with pytest.raises(ValueError, match=r"^tools\[2\]\.feed: missing"):
        ToolpathProblem(tools=tools, **kw)


def test_an_nc_operation_pays_its_rapids_and_plunges_at_their_rates():
    from evoplan.problems.toolpath.criteria.kinematic_time import toolpath_time
    from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath

    # rapid down 40 mm, plunge 10 mm at 600 mm/min, cut 200 mm at 5000, rapid up 50 mm
    tp = Toolpath("op", Tool(1, make_cutter(10, 0)), [[0, 0, 50], [0, 0, 10], [0, 0, 0], [200, 0, 0], [200, 0, 50]],
                  np.tile([0, 0, 1.0], (5, 1)), [1, 1, 0, 0, 1], [0, 0, 1, 0, 0], [-1, -1, 0, 0, -1],
                  feed=5000.0, plunge_feed=600.0)
    R, P = 10000 / 60, 600 / 60
    # the plunge's bottom corner (90 deg, v_c 12 mm/s) does not stop it: it ends at P, the cut starts at P
    t1, tp1 = t_change(P), t_change(F - P)
    plunge = t1 + (10 - P / 2 * t1) / P
    cut = tp1 + t_change(F) + (200 - (P + F) / 2 * tp1 - F / 2 * t_change(F)) / F
    want = (40 / R + t_change(R)) + plunge + cut + (50 / R + t_change(R))
    assert toolpath_time(tp, Dynamics(rapid=10000.0)) * 60 == pytest.approx(want, rel=1e-9)


def test_program_moves_pay_a_rotary_turn_in_a_rapid_at_the_rotary_rate():
    from evoplan.problems.toolpath.criteria.kinematic_time import moves_time

    # at the clearance plane: C turns 180 deg in place (a rapid), then a 200 mm feed move
    tip = [[0, 0, 50], [0, 0, 50], [200, 0, 50]]
    angles = [[10, 0], [10, 180], [10, 180]]
    rapid, feed = [True, True, False], [np.nan, np.nan, 5000.0]
    cut = 200 / F + t_change(F)  # rest to rest at F
    assert moves_time(tip, rapid, feed, DYN) * 60 == pytest.approx(cut, rel=1e-9)  # no rotaries: 0 s turn
    with_turn = moves_time(tip, rapid, feed, DYN, angles=angles, rapid_rotary=5400.0) * 60
    assert with_turn == pytest.approx(cut + 180 / 5400 * 60, rel=1e-9)  # + 2 s


def test_the_machine_summary_times_the_program_as_written():
    # a finish that repositions at the clearance plane (abbas_gentle: 10 times) takes longer than
    # its path length / feed, which summary.json's time_min alone hides (abbas_wide_z: 103
    # repositions, 8.1 min against 2.2)
    from evoplan.commands.machine import load
    from evoplan.problems.toolpath.roughing.operation_set import build_operations
    from pathlib import Path

    runs = Path(__file__).resolve().parents[3] / "runs"
    cfg = load(str(runs / "abbas_gentle.yaml")).model_dump()
    _, s = build_operations(cfg, runs)
    for op in ("roughing", "semifinish", "finish"):
        assert s[op]["kinematic_time_min"] >= s[op]["time_min"] * 0.999, op
    assert s["finish"]["safety"]["repositions"] == 10
    assert s["finish"]["kinematic_time_min"] > 1.2 * s["finish"]["time_min"]  # 2.63 against 2.11 min
