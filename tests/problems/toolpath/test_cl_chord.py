"""Chord tolerance of a 3-axis plan's CL points (``Planner.cl_path``): the straight moves
between drop-cutter CL points stay within the tolerance of the drop-cutter CL curve, and
the cut simulation no longer finds a gouge above it."""

import numpy as np
import pytest
from evoplan.problems.toolpath.cutters import make_cutter
from toolpath_analytic import GraphSurface

from evoplan.problems.toolpath import ToolpathProblem
from evoplan.problems.toolpath.plan.planner import Planner
from evoplan.problems.toolpath.simulation import design_grid, simulate
from evoplan.problems.toolpath.spec import parse_tools

TOL = 0.01


class Ridge(GraphSurface):
    """z = 20 - 0.1 (x - 50)^2 over [35, 65] x [0, 20]: curvature radius 5 mm on the crest,
    slope 3 at the edges (convex along x)."""

    def __init__(self):
        super().__init__(35.0, 65.0, 0.0, 20.0)

    def height(self, x, y):
        d = x - 50.0
        z0 = np.zeros_like(x)
        return 20.0 - 0.1 * d * d, -0.2 * d, z0, z0 - 0.2, z0, z0


ALPHA, DELTA = 0.2, 4.0


def _paths(d, r, tolerance=TOL, rounds=8):
    """(raw, refined, cutter, plane offsets): one zone fed at 0.2 rad from x (the crest
    crossed at a slant), 3-axis drop-cutter, planes 4 mm apart in XY, CC points at most
    2 mm apart. raw: the plan's CL points as placed; refined: ``Planner.cl_path`` with the
    chord tolerance (``rounds`` rounds)."""
    tools = parse_tools([{"diameter": d, "corner_radius": r}])
    planner = Planner(Ridge(), tools, machine="3axis", placement="drop", tolerance=tolerance,
                      feed_angle=float(np.degrees(ALPHA)))
    genes = {"tool": [0], "stepover": [100.0 * DELTA / d], "step": [2.0]}
    batch = planner.plan({k: np.asarray(v) for k, v in genes.items()})
    raw = batch.cl_path(0, make_cutter(d, r))
    return raw, planner.cl_path(genes, chord_rounds=rounds), tools.cutter(0), batch.sec_d


def _dense_deviation(surface, cutter, path, n=24):
    """Largest |drop-cutter tip z - chord z| at n - 1 interior points of every move."""
    same = np.flatnonzero(path.section[1:] == path.section[:-1])
    q = np.linspace(0.0, 1.0, n + 1)[1:-1, None, None]
    a, b = path.tip[same], path.tip[same + 1]
    chord = (1 - q) * a + q * b
    z = cutter.drop_cutter(surface, chord[..., :2].reshape(-1, 2)).reshape(chord.shape[:2])
    return float(np.abs(z - chord[..., 2]).max())


@pytest.mark.parametrize("d, r", [(8.0, 1.0), (6.35, 3.175)])
def test_refined_moves_stay_within_tolerance_of_the_drop_cutter_curve(d, r):
    surface = Ridge()
    raw, path, cutter, planes = _paths(d, r)
    assert "chord_tolerance" not in raw.info
    assert _dense_deviation(surface, cutter, raw) > 5 * TOL  # the unrefined chords leave it
    assert _dense_deviation(surface, cutter, path) <= TOL
    info = path.info
    assert 0 < info["chord_added"] <= len(path) - len(raw)
    assert info["chord_deviation"] <= TOL and info["chord_tolerance"] == TOL
    # every raw CL point is kept; the new ones lie on the same planes, sections, XY steps
    assert np.all(np.isin(raw.tip[:, 0], path.tip[:, 0]))
    assert np.array_equal(np.unique(path.section), np.unique(raw.section))
    same = path.section[1:] == path.section[:-1]
    on = path.info["on_part"]  # (the runs past the part's edges hold no CC point)
    cc_step = np.linalg.norm(np.diff(path.info["cc"][:, :2], axis=0), axis=1)[same & on[1:] & on[:-1]]
    assert cc_step.max() <= 2.0 + 1e-9  # the CC points keep the step; new tips split moves
    assert path.info["inserted"].sum() == info["chord_added"]
    assert np.allclose(path.tip[:, 2], cutter.drop_cutter(surface, path.tip[:, :2]))
    off = path.info["cc"][:, :2] @ [-np.sin(ALPHA), np.cos(ALPHA)]
    assert np.abs(off[:, None] - planes[None]).min(axis=1).max() < 1e-6


def test_simulated_gouge_falls_to_the_tolerance():
    raw, path, _, _ = _paths(8.0, 1.0)
    grid = design_grid(Ridge(), 0.2)
    gouge = {tol: simulate(p, grid).metrics["gouge_max_mm"] for tol, p in ((None, raw), (TOL, path))}
    assert gouge[None] > 3 * TOL
    assert gouge[TOL] <= TOL + 2e-3  # the chord's deviation plus the sweep's search error


def test_round_limit_and_bad_tolerance():
    raw, one, _, _ = _paths(8.0, 1.0, tolerance=1e-4, rounds=1)
    assert one.info["chord_rounds"] == 1 and one.info["chord_deviation"] > 1e-4
    added = one.info["chord_added"]
    assert 0 < added <= len(raw) - 1  # one split per move at most
    with pytest.raises(ValueError, match="tolerance: must be a finite number > 0"):
        ToolpathProblem(surface=Ridge(), machine="3axis", tolerance=0.0)
