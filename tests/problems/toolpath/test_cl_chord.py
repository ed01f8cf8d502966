"""Chord tolerance of a zoning plan's CL points: the straight moves between drop-cutter CL
points stay within the tolerance of the drop-cutter CL curve, and the cut simulation no
longer finds a gouge above it."""

import numpy as np
import pytest
from toolpath_analytic import GraphSurface

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.simulation import design_grid, simulate
from evoplan.problems.toolpath.plan.zoning.cl_points import zone_cl_path
from evoplan.problems.toolpath.plan.zoning.passes import ZonePasses
from evoplan.problems.toolpath.plan.zoning.plan import ZonePlan, ZoningPlan

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


ALPHA, PLANES = 0.2, np.arange(-10.0, 11.0, 4.0)


def _plan():
    """One zone over the whole mesh fed at 0.2 rad from x (the crest crossed at a slant)
    on the planes c . xy = -10, -6, ..., 10 (c = (-sin a, cos a))."""
    alpha, s = ALPHA, PLANES
    zone = ZonePlan(0, 100, 100.0, 0.0, np.degrees(alpha), 0.0,
                    ZonePasses(alpha, s, np.full(len(s), 30.0), np.diff(s)), 0.0, 0)
    return ZoningPlan("single", np.zeros((10, 10), np.int64), [zone], 0.0, {})


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
    surface, plan, cutter = Ridge(), _plan(), make_cutter(d, r)
    raw = zone_cl_path(surface, plan, cutter, step=2.0, tolerance=None)
    path = zone_cl_path(surface, plan, cutter, step=2.0, tolerance=TOL)
    assert raw.info["chord_tolerance"] is None
    assert _dense_deviation(surface, cutter, raw) > 5 * TOL  # the unrefined chords leave it
    assert _dense_deviation(surface, cutter, path) <= TOL
    info = path.info
    assert info["chord_added"] == len(path) - len(raw) > 0
    assert info["chord_deviation"] <= TOL and info["chord_tolerance"] == TOL
    # every raw CL point is kept; the new ones lie on the same planes, sections, XY steps
    assert np.all(np.isin(raw.tip[:, 0], path.tip[:, 0]))
    assert np.array_equal(np.unique(path.section), np.unique(raw.section))
    same = path.section[1:] == path.section[:-1]
    assert np.linalg.norm(np.diff(path.tip[:, :2], axis=0), axis=1)[same].max() <= 2.0 + 1e-9
    assert np.allclose(path.tip[:, 2], cutter.drop_cutter(surface, path.tip[:, :2]))
    off = path.info["cc"][:, :2] @ [-np.sin(ALPHA), np.cos(ALPHA)]
    assert np.abs(off[:, None] - PLANES[None]).min(axis=1).max() < 1e-6


def test_simulated_gouge_falls_to_the_tolerance():
    surface, plan, cutter = Ridge(), _plan(), make_cutter(8.0, 1.0)
    grid = design_grid(surface, 0.2)
    gouge = {tol: simulate(zone_cl_path(surface, plan, cutter, step=2.0, tolerance=tol),
                           grid).metrics["gouge_max_mm"] for tol in (None, TOL)}
    assert gouge[None] > 3 * TOL
    assert gouge[TOL] <= TOL + 2e-3  # the chord's deviation plus the sweep's search error


def test_round_limit_and_bad_tolerance():
    surface, plan, cutter = Ridge(), _plan(), make_cutter(8.0, 1.0)
    one = zone_cl_path(surface, plan, cutter, step=2.0, tolerance=1e-4, rounds=1)
    assert one.info["chord_rounds"] == 1 and one.info["chord_deviation"] > 1e-4
    raw = zone_cl_path(surface, plan, cutter, step=2.0, tolerance=None)
    assert len(raw) < len(one) <= 2 * len(raw)  # one split per move at most
    with pytest.raises(ValueError, match="tolerance: must be a number > 0"):
        zone_cl_path(surface, plan, cutter, tolerance=0.0)
