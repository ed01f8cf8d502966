"""A trimmed face with a hole and a notch (the sample STEP part's top): every pass plane is cut
into its crossings of the footprint, and no CC point and no simulated cell lies off the face."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

from evoplan.problems.toolpath.geometry.cad_faces import DEFLECTION  # noqa: E402
from evoplan.problems.toolpath.geometry.crossings import inside, line_intervals  # noqa: E402
from evoplan.problems.toolpath.geometry.spec import parse_surface  # noqa: E402
from evoplan.problems.toolpath.plan.planner import Planner  # noqa: E402
from evoplan.problems.toolpath.plan.zones import ZoningSpec  # noqa: E402
from evoplan.problems.toolpath.simulation import design_grid, sweep_path  # noqa: E402
from evoplan.problems.toolpath.spec import parse_tools  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]
PART = ROOT / "runs" / "parts" / "sculpted_block.step"
HX, HY, HR = 65.0, 40.0, 8.0  # runs/parts/make_step_part.py: HOLE
NOTCH = (30.0, 30.0, 50.0)  # x < 30 with 30 < y < 50 is cut away
BALL = [{"id": 1, "type": "ball", "diameter": 6.0}]


@pytest.fixture(scope="module")
def top():
    return parse_surface({"type": "step", "file": str(PART), "face": "largest"})


def off_face(xy, margin):
    """Points more than ``margin`` mm inside the hole or the notch, or off the block."""
    x, y = xy[:, 0], xy[:, 1]
    hole = np.hypot(x - HX, y - HY) < HR - margin
    nx, ny0, ny1 = NOTCH
    notch = (x < nx - margin) & (y > ny0 + margin) & (y < ny1 - margin)
    block = (x < -margin) | (x > 100 + margin) | (y < -margin) | (y > 80 + margin)
    return hole | notch | block


def test_the_top_face_is_the_trimmed_free_form_face(top):
    assert len(top.footprint.loops) == 2  # the outer wire (with the notch) and the hole
    xy = top.footprint.xy_loops(top)
    hole = xy[1]
    assert np.abs(np.hypot(hole[:, 0] - HX, hole[:, 1] - HY) - HR).max() < 2 * DEFLECTION


def test_crossings_split_lines_at_holes():
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    hole = np.array([[1, 1], [3, 1], [3, 3], [1, 3]], float)
    line, xa, xb, first, last = line_intervals([square, hole], np.array([2.0, 0.5]))
    assert line.tolist() == [0, 0, 1] and xa.tolist() == [0, 3, 0] and xb.tolist() == [1, 4, 4]
    assert first.tolist() == [True, False, True] and last.tolist() == [False, True, True]
    pts = np.array([[2, 2], [0.5, 2], [3.5, 3.5], [5, 2]], float)
    assert inside([square, hole], pts[:, 0], pts[:, 1]).tolist() == [False, True, True, False]


@pytest.mark.parametrize("zoned", [False, True])
def test_no_cc_point_and_no_cut_cell_in_the_hole(top, zoned):
    """A 3-axis ball plan along X: planes through the hole are cut in two sections, its CC
    points keep off the hole and the notch (to the trimming curves' sampling, 1e-3 mm), and
    the cut simulation counts no cell there, yet cuts the face around them."""
    kw = dict(zoning=ZoningSpec("kmeans", mesh=(24, 24)), feed_angle=None) if zoned else {}
    planner = Planner(top, parse_tools(BALL), machine="3axis", tolerance=0.01, **kw)
    genes = {"tool": [0], "stepover": [45.0], "step": [3.0]} | ({"zones": [2]} if zoned else {})
    batch = planner.plan({k: np.asarray(v) for k, v in genes.items()})
    cc = batch.p[batch.on_part]
    assert len(cc) > 200 and not off_face(cc[:, :2], 2 * DEFLECTION).any()
    if not zoned:  # planes 32 < y < 48 meet the face twice: left and right of the hole
        per_plane = np.bincount(batch.sec_pass)
        d = np.array([batch.sec_d[batch.sec_pass == k][0] for k in range(len(per_plane))])
        through = np.abs(d - HY) < HR
        assert through.sum() >= 3 and (per_plane == np.where(through, 2, 1)).all()
    grid = design_grid(top, 0.5)
    cx, cy = np.meshgrid(grid.xs, grid.ys)
    centres = np.column_stack([cx.ravel(), cy.ravel()])
    assert not grid.inside.ravel()[off_face(centres, 0.3)].any()  # no cell in the hole
    res = sweep_path(planner.cl_path({k: [v[0]] for k, v in genes.items()}), grid).values
    cut = grid.inside & np.isfinite(res) & (res < 0.5)
    assert cut.sum() > 0.95 * grid.inside.sum()  # the face around the hole is machined


def _plan_on_the_face(top, strategy):
    """A 3-axis ball plan of the face with ``strategy``: (batch, the CC points on the part),
    checked to be finite, off the hole and the notch, and to machine 95 % of the face."""
    planner = Planner(top, parse_tools(BALL), machine="3axis", spacing="scallop", h_c=0.254,
                      feed_angle=0.0, strategy=strategy)
    genes = {"tool": np.array([0]), "step": np.array([3.0])}
    batch = planner.plan(genes)
    assert np.isfinite(batch.tip).all()
    cc = batch.p[batch.on_part]
    assert len(cc) > 500 and not off_face(cc[:, :2], 2 * DEFLECTION).any()
    grid = design_grid(top, 0.5)
    res = sweep_path(planner.cl_path(genes), grid).values
    cut = grid.inside & np.isfinite(res) & (res < 0.5)
    assert cut.sum() > 0.95 * grid.inside.sum()
    return batch, cc


@pytest.mark.parametrize("strategy", ["isoscallop", "isoparametric"])
def test_curve_passes_are_cut_at_the_trimming_loops(top, strategy):
    """Iso-scallop offsets propagate across the hole and iso-parametric curves run over it,
    but both are cut where they leave the face (iso-scallop: 130 of 1225 CC points lay in
    the hole or the notch before; iso-parametric: its points there dropped to -inf and the
    plan was refused): every CL point finite, none off the face, the face machined."""
    _plan_on_the_face(top, strategy)


def test_contour_loops_go_round_the_hole_and_stay_on_the_face(top):
    """Contour offsets of a trimmed face are offsets of its footprint, hole included: every
    CL point is finite (the square's image and the corner passes across the hole and the
    notch made -inf drops before), no CC point is off the face, loops run round the hole
    within one spacing of it, and the face is machined."""
    _, cc = _plan_on_the_face(top, "contour")
    ring = np.hypot(cc[:, 0] - HX, cc[:, 1] - HY)
    near = (ring > HR) & (ring < HR + 3.0)  # within a spacing of the hole's edge
    angles = np.arctan2(cc[near, 1] - HY, cc[near, 0] - HX)
    assert np.histogram(angles, bins=12, range=(-np.pi, np.pi))[0].min() > 0  # all the way round


def test_the_committed_part_is_what_its_script_makes(tmp_path):
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_step_part",
                                                  ROOT / "runs" / "parts" / "make_step_part.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.main(["--out", str(tmp_path / "part.step")]) == 0
    made = parse_surface({"type": "step", "file": str(tmp_path / "part.step"), "face": "largest"})
    shipped = parse_surface({"type": "step", "file": str(PART), "face": "largest"})
    assert np.abs(made.poles - shipped.poles).max() < 1e-9
    assert [len(lp) for lp in made.footprint.loops] == [len(lp) for lp in shipped.footprint.loops]
    assert max(np.abs(a - b).max() for a, b in zip(made.footprint.loops,
                                                    shipped.footprint.loops)) < 1e-9


def test_contour_ridges_between_the_hole_and_the_edges_are_cut(top):
    """Between the hole and the block's edges the offsets pinch: their fronts meet head-on
    at x = 43.7 and x = 86.5, where the last loop before the pinch passes farther than its
    reach on both sides (ball D6, h_c 0.05: cells there were left 0.137 mm high on the
    0.2 mm grid). Ridge passes along those strips leave every cell of the face within
    1.1 h_c, for 2.3 % more length."""
    planner = Planner(top, parse_tools(BALL), machine="3axis", spacing="scallop", h_c=0.05,
                      tolerance=0.01, feed_angle=0.0, strategy="contour")
    genes = {"tool": np.array([0]), "step": np.array([2.0])}
    grid = design_grid(planner.surface, 0.2)
    res = sweep_path(planner.cl_path(genes), grid).values[grid.inside]
    assert np.isfinite(res).all() and res.max() <= 1.1 * 0.05


def test_iso_scallop_offsets_stopped_at_the_domain_edge_keep_finite_widths(top):
    """Where the walk to the next pass stops several points at one spot of the domain's
    edge, the next pass has no direction of its own there; its width used to be 0 / 0 (a
    RuntimeWarning from the curvature, then nan uv cast to grid indices): now this pass's
    direction is used, and planning raises no floating-point warning."""
    import warnings

    planner = Planner(top, parse_tools(BALL), machine="3axis", spacing="scallop", h_c=0.05,
                      tolerance=0.01, feed_angle=0.0, strategy="isoscallop")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        batch = planner.plan({"tool": np.array([0]), "step": np.array([2.0])})
    assert np.isfinite(batch.p).all() and np.isfinite(batch.tip).all()


def test_iso_scallop_corner_passes_close_the_gap_a_swallowtail_leaves(top, monkeypatch):
    """Where a pass bends towards its offsets, the next pass's swallowtail is cut and leaves
    a sharp corner gap / sin(theta / 2) from the bend; between them both passes are farther
    than their reach. On the block's top (torus D10 r2, h_c 0.05) the cells there, around
    (33.8, 73.3), were left 0.133 mm high; a corner pass from the corner to the bend brings
    them within 1.1 h_c."""
    from evoplan.problems.toolpath.plan.strategies import isoscallop

    torus = [{"id": 3, "type": "toroidal", "diameter": 10.0, "corner_radius": 2.0}]
    genes = {"tool": np.array([0]), "step": np.array([2.0])}
    grid = design_grid(top, 0.2)
    cx, cy = np.meshgrid(grid.xs, grid.ys)
    window = grid.inside & (np.abs(cx - 33.8) < 2.5) & (np.abs(cy - 73.5) < 2.5)
    worst = {}
    for corners in (False, True):
        if not corners:
            monkeypatch.setattr(isoscallop, "_corner_passes", lambda *a, **k: [])
        else:
            monkeypatch.undo()
        planner = Planner(top, parse_tools(torus), machine="3axis", spacing="scallop",
                          h_c=0.05, tolerance=0.01, feed_angle=0.0, strategy="isoscallop")
        worst[corners] = sweep_path(planner.cl_path(genes), grid).values[window].max()
    assert worst[False] > 2 * 0.05 and worst[True] <= 1.1 * 0.05


def test_untangle_reports_the_corner_each_cut_leaves():
    from evoplan.problems.toolpath.plan.strategies.offsets import untangle

    uv = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1.5, -1], [3, -1], [4, -1]], float)
    cut = []
    out = untangle(uv, crossings=cut)
    assert len(cut) == 1 and np.allclose(cut[0][0], out[2]) and cut[0][1] == 2
