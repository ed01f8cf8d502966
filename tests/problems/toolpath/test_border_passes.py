"""Border passes (``plan/border.py``): a trimmed face's edges that the passes leave above the
scallop target are cut along the edge; edges the passes already cut, plans without a
scallop target and whole footprints are left as they are."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.plan.border import REACH, BorderLoops, PairReach, with_border
from evoplan.problems.toolpath.plan.planner import Planner
from evoplan.problems.toolpath.spec import parse_tools

ROOT = Path(__file__).resolve().parents[3]
PART = ROOT / "runs" / "parts" / "sculpted_block.step"
H_C = 0.05
BALL = [{"id": 1, "type": "ball", "diameter": 6.0}]
GENES = {"tool": np.array([0]), "step": np.array([2.0])}


@pytest.fixture(scope="module")
def top():
    pytest.importorskip("OCP")
    from evoplan.problems.toolpath.geometry.spec import parse_surface

    return parse_surface({"type": "step", "file": str(PART), "face": "largest"})


def _planner(surface, strategy, border, tools=BALL):
    return Planner(surface, parse_tools(tools), machine="3axis", spacing="scallop", h_c=H_C,
                   tolerance=0.01, feed_angle=0.0, strategy=strategy, border_passes=border)


def _notch_sides(grid, values):
    """The residual (mm) of the cells on the part within 1 mm of the notch's sides y = 30 and
    y = 50 (x < 30), which run along the X feed (``runs/parts/make_step_part.py``)."""
    cx, cy = np.meshgrid(grid.xs, grid.ys)
    near = (cx < 29.0) & ((np.abs(cy - 30.0) < 1.0) | (np.abs(cy - 50.0) < 1.0)) & grid.inside
    res = values[near]
    assert near.sum() > 200 and np.isfinite(res).all()
    return res


def _on_part_length(batch):
    """The feed moves' length (mm) between CC points on the part."""
    move = (batch.pt_sec[1:] == batch.pt_sec[:-1]) & batch.on_part[1:] & batch.on_part[:-1]
    return float(np.linalg.norm(np.diff(batch.p, axis=0), axis=1)[move].sum())


def test_border_passes_cut_the_notch_sides_the_parallel_passes_leave_high(top):
    """A ball D6 parallel plan at h_c 0.05 along X ends 0.9 and 1.5 mm from the notch's
    sides, beyond the ball's reach at h_c (0.545 mm): the simulated cells along them are
    left about 2-3 h_c high. With the border passes every cell there is within 1.1 h_c, on
    the 0.2 mm grid and in the whole face, and the plan is at most 10 % longer."""
    from evoplan.problems.toolpath.simulation import design_grid, sweep_path

    grid = design_grid(top, 0.2)
    out = {}
    for border in (False, True):
        planner = _planner(top, "parallel", border)
        batch = planner.plan(GENES)
        length = _on_part_length(batch)
        values = sweep_path(planner.cl_path(GENES), grid).values
        out[border] = (_notch_sides(grid, values).max(), values[grid.inside], length, batch)
    assert out[False][0] > 2.0 * H_C
    assert out[True][0] <= 1.1 * H_C
    assert np.nanmax(out[True][1]) <= 1.1 * H_C
    assert out[False][2] < out[True][2] < 1.1 * out[False][2]
    plain, bordered = out[False][3], out[True][3]
    k = len(plain.p)  # the plan's own passes first, unchanged; the border sections after
    assert np.array_equal(bordered.p[:k], plain.p) and len(bordered.sec_ind) > len(plain.sec_ind)


def test_plans_that_cover_their_edges_get_no_border_passes(top):
    """Contour loops start on the edge: every loop point is covered, the plan is unchanged."""
    plain = _planner(top, "contour", False).plan(GENES)
    bordered = _planner(top, "contour", True).plan(GENES)
    assert np.array_equal(plain.p, bordered.p) and np.array_equal(plain.sec_ind, bordered.sec_ind)


def test_a_torus_s_passes_cover_the_edges_they_cross(top):
    """The D10 r2 torus's passes along X cross the block's edges x = 0 and x = 100: they
    cover them with their flat bottom across the feed (3.44 mm at h_c), not with the
    corner's 0.44 mm a pass along a sloping edge has, so only the notch's sides are
    bordered and the plan grows by a few per cent (27 % when the width was taken across the
    loop everywhere)."""
    torus = [{"id": 3, "type": "toroidal", "diameter": 10.0, "corner_radius": 2.0}]
    plain = _on_part_length(_planner(top, "parallel", False, torus).plan(GENES))
    bordered = _planner(top, "parallel", True, torus).plan(GENES)
    assert plain < _on_part_length(bordered) < 1.05 * plain
    border = bordered.p[bordered.sec_start[-1]:]  # the last border section
    assert np.ptp(border[:, 0]) > 5.0
    # every border point lies along the notch's sides, none on the edges the passes cross
    k = len(_planner(top, "parallel", False, torus).plan(GENES).p)
    xy = bordered.p[k:, :2]
    assert len(xy) and np.all((xy[:, 0] < 33.0) & ((np.abs(xy[:, 1] - 30.0) < 3.0)
                                                   | (np.abs(xy[:, 1] - 50.0) < 3.0)))


def test_whole_footprints_and_plans_without_h_c_are_returned_as_they_are(top):
    from toolpath_analytic import Plane

    plane = Plane(0.0, 40.0, 0.0, 30.0, a=0.1)
    planner = _planner(plane, "parallel", True)
    batch = _planner(plane, "parallel", False).plan(GENES)
    assert with_border(planner, batch, GENES, True) is batch
    stepover = Planner(top, parse_tools(BALL), machine="3axis", tolerance=0.01)
    genes = dict(GENES, stepover=np.array([45.0]))
    batch = Planner(top, parse_tools(BALL), machine="3axis", tolerance=0.01,
                    border_passes=False).plan(genes)
    assert with_border(stepover, batch, genes, True) is batch


def test_a_torus_crossing_an_edge_covers_it_with_its_flat_bottom():
    """Vertical D10 r2 at h_c 0.05: beside a level move the profile rises to h at
    R - r + sqrt(2 r h - h^2) = 3.444 mm (the flat bottom, then the corner); across a slope
    of 0.3 rad the torus touches with its corner and, up or down the slope, the profile
    rises to h within the corner, under 0.6 mm; a 5-axis tool, square to the surface, has
    the level width on every side."""
    torus = make_cutter(10.0, 2.0)
    flat = 3.0 + np.sqrt(2 * 2.0 * H_C - H_C**2)
    reach = PairReach({7: torus}, np.array([7, 7]), H_C, vertical=True)
    r = reach(np.array([0, 1, 1]), np.zeros(3), np.array([0.0, 0.3, -0.3]))
    assert r[0] == pytest.approx(REACH * flat, rel=1e-6)
    assert r[1] < REACH * 0.6 and r[2] < REACH * 0.6
    assert reach.bound.tolist() == pytest.approx([REACH * flat] * 2, rel=1e-6)
    # the table never claims more than the exact width, and is within 5 % of it at most
    # samples off the level
    rng = np.random.default_rng(3)
    tz, beta = rng.uniform(0.0, 1.0, 400), rng.uniform(-1.5, 1.5, 400)
    exact = REACH * np.minimum(torus.swept_side_width(H_C, tz, beta), flat)
    got = reach(np.zeros(400, np.int64), tz, beta)
    assert np.all(got <= exact + 1e-12) and np.mean(got >= 0.95 * exact) > 0.9
    five = PairReach({7: torus}, np.array([7]), H_C, vertical=False)
    assert five(np.array([0]), np.zeros(1), np.array([0.3]))[0] == pytest.approx(REACH * flat)


def test_loop_stretches_wrap_round_the_loop_start():
    """Runs of points to cut are read round each loop: a run over the start is one
    stretch, widened at both ends; a run that spans the loop is the loop, closed."""
    loops = BorderLoops.__new__(BorderLoops)
    loops.start, loops.end = np.array([0, 20]), np.array([20, 30])
    cut = np.zeros(30, bool)
    cut[[18, 19, 0, 1]] = True  # over loop 0's start
    cut[25] = True
    got = loops.stretches(cut, widen=1)
    assert [g.tolist() for g in got] == [[17, 18, 19, 0, 1, 2], [24, 25, 26]]
    cut[20:30] = True
    assert loops.stretches(cut, widen=1)[1].tolist() == list(range(20, 30)) + [20]


def test_the_spec_key_turns_border_passes_off():
    from evoplan.problems.toolpath import ToolpathProblem
    from evoplan.problems.toolpath.spec.model import ToolpathSpec

    assert ToolpathProblem(border_passes=False).planner.border_passes is False
    assert ToolpathProblem().planner.border_passes is True
    with pytest.raises(ValueError, match="border_passes"):
        ToolpathSpec(border_passes="sometimes")
