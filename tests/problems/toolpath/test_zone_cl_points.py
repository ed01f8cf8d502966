"""CL points of a zoned 3-axis plan (``Planner.cl_path``): sections on their planes, two
zones each fed along its own flank, zig-zag, tangent (cc) and drop-cutter placements."""

import numpy as np
import pytest
from scipy.spatial import cKDTree
from test_zoning_methods import Strips
from toolpath_analytic import GraphSurface

from evoplan.problems.toolpath import ToolpathProblem
from evoplan.problems.toolpath.plan.planner import Planner
from evoplan.problems.toolpath.plan.zones import ZoningSpec
from evoplan.problems.toolpath.plan.zoning.methods import register, unregister
from evoplan.problems.toolpath.spec import parse_tools

SLOPE = 0.4
STEP = 1.0


class Roof(GraphSurface):
    """Two planes meeting at x = 50 over [0, 100] x [0, 60]: a ridge (sign +1, z = 20 -
    0.4 |x - 50|) or a valley (sign -1, z = 0.4 |x - 50|)."""

    def __init__(self, sign=1.0):
        self.sign = sign
        super().__init__(0.0, 100.0, 0.0, 60.0)

    def height(self, x, y):
        d = x - 50.0
        z0 = np.zeros_like(x)
        if self.sign > 0:
            return 20.0 - SLOPE * np.abs(d), -SLOPE * np.sign(d), z0, z0, z0, z0
        return SLOPE * np.abs(d), SLOPE * np.sign(d), z0, z0, z0, z0


def _plane_tip_z(x, y, side, cutter):
    """Closed form: a torus resting on the (extended) plane of one side of the ridge."""
    r, r0 = cutter.corner_radius, cutter.radius - cutter.corner_radius
    s = np.arctan(SLOPE)
    z = 20.0 + side * SLOPE * (x - 50.0)
    return z + r0 * np.tan(s) + r * (1 / np.cos(s) - 1)


def _max_penetration(surface, cutter, tip, n=400):
    """Largest height of a dense grid point of the surface above the cutter's profile."""
    t = np.linspace(0, 1, n)
    uu, vv = np.meshgrid(t, t, indexing="ij")
    pts = surface.points(uu.ravel(), vv.ravel())
    lists = cKDTree(pts[:, :2]).query_ball_point(tip[:, :2], cutter.radius)
    idx = np.concatenate([np.asarray(x, int) for x in lists])
    owner = np.repeat(np.arange(len(tip)), [len(x) for x in lists])
    rho = np.hypot(*(pts[idx, :2] - tip[owner, :2]).T)
    return float((pts[idx, 2] - tip[owner, 2] - cutter.height(rho)).max())


@pytest.fixture(scope="module")
def halves():
    """A zoning method (a test's) that cuts the mesh in two along u: the zones are the two
    flanks (the ridge x = 50 is the cell border u = 0.5)."""
    method = register(Strips)
    yield method
    unregister(method.name)


def _planner(surface, d, r, placement):
    """Two zones (u < 1/2, u > 1/2), each fed along its optimized direction, 3-axis."""
    return Planner(surface, parse_tools([{"diameter": d, "corner_radius": r}]), machine="3axis",
                   placement=placement, feed_angle=None,
                   zoning=ZoningSpec("strips_test", settings={"strips": 2}, mesh=(20, 12),
                                     merge=None))


GENES = {"tool": np.array([0]), "stepover": np.array([80.0]), "step": np.array([STEP])}


@pytest.mark.parametrize("d, r", [(8.0, 0.0), (8.0, 1.0), (8.0, 4.0)])
def test_zoned_plan_points_lie_on_their_planes_and_closed_form_tips(halves, d, r):
    surface = Roof()
    planner = _planner(surface, d, r, "cc")
    batch = planner.plan(GENES)
    path = planner.cl_path(GENES)
    cc = path.info["cc"]
    assert batch.zones.tolist() == [2] and set(path.zone.tolist()) == {0, 1}
    assert np.allclose(cc[:, 2], 20.0 - SLOPE * np.abs(cc[:, 0] - 50.0), atol=1e-9)
    for z in (0, 1):
        secs = np.flatnonzero(batch.sec_zone == z)
        a = batch.sec_alpha[secs[0]]
        assert np.all(batch.sec_alpha[secs] == a)  # one feed direction per zone
        f, c = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        travel = []
        for k in np.unique(batch.sec_pass[secs]):
            s = secs[batch.sec_pass[secs] == k]
            idx = np.concatenate([np.arange(batch.sec_start[i], batch.sec_start[i] + batch.sec_count[i])
                                  for i in s])
            assert np.allclose(batch.p[idx, :2] @ c, batch.sec_d[s[0]], atol=1e-6)  # on its plane
            dt = np.diff(batch.p[batch.sec_start[s[0]]:batch.sec_start[s[0]] + batch.sec_count[s[0]], :2] @ f)
            assert np.all(np.abs(dt) <= STEP + 1e-9) and (np.all(dt > 0) or np.all(dt < 0))
            travel.append(np.sign(dt[0]))
        assert len(travel) > 2 and np.all(np.array(travel[1:]) == -np.array(travel[:-1]))  # zig-zag
    off_ridge = np.abs(cc[:, 0] - 50.0) > 1e-6
    side = np.where(cc[:, 0] < 50, 1.0, -1.0)
    expect = _plane_tip_z(path.tip[:, 0], path.tip[:, 1], side, planner.tools.cutter(0))
    assert np.allclose(path.tip[off_ridge, 2], expect[off_ridge], atol=1e-9)  # tangent to its flank
    assert path.cutter.diameter == d and path.cutter.corner_radius == r
    assert np.allclose(path.axis, [0, 0, 1])


@pytest.mark.parametrize("d, r", [(8.0, 0.0), (8.0, 1.0), (8.0, 4.0)])
def test_drop_placement_is_the_plane_closed_form_away_from_the_ridge_and_never_gouges(halves, d, r):
    surface = Roof()
    planner = _planner(surface, d, r, "drop")
    cutter = planner.tools.cutter(0)
    path = planner.cl_path(GENES)
    x, y = path.tip[:, 0], path.tip[:, 1]
    side = np.where(x < 50, 1.0, -1.0)
    plane = _plane_tip_z(x, y, side, cutter)  # the torus resting on the flank below its axis
    inside = (x > d / 2) & (x < 100 - d / 2) & (y > d / 2) & (y < 60 - d / 2)
    far = inside & (np.abs(x - 50) > d / 2 + 1e-9)
    # (a flat end touches a flank with its uphill rim: its tip stays R downhill of the CC
    # point, so no tip placed at a CC point comes within R of the crest; the moves that
    # cross the crest get tips of their own there, where a straight move would cut it)
    placed = ~path.info["inserted"]
    assert far.sum() > 50 and ((inside & ~far & placed).sum() > 5 if r > 0
                               else not (inside & ~far & placed).any())
    assert np.allclose(path.tip[far, 2], plane[far], atol=1e-9)
    assert np.all(path.tip[inside & ~far, 2] <= plane[inside & ~far] + 1e-9)  # the ridge falls away
    assert _max_penetration(surface, cutter, path.tip) < 1e-9


def test_cc_placement_gouges_a_valley_and_the_drop_does_not(halves):
    surface = Roof(sign=-1.0)
    # (plans without the CL chord refinement: both placements on the same CC points)
    tangent = _planner(surface, 8.0, 1.0, "cc").plan(GENES)
    drop = _planner(surface, 8.0, 1.0, "drop").plan(GENES)
    on = drop.on_part
    assert np.array_equal(tangent.p, drop.p[on]) and set(tangent.sec_zone.tolist()) == {0, 1}
    cutter = parse_tools([{"diameter": 8.0, "corner_radius": 1.0}]).cutter(0)
    # tangent at the CC point, the torus cuts into the other flank near the valley floor
    assert _max_penetration(surface, cutter, tangent.tip) > 0.1
    assert _max_penetration(surface, cutter, drop.tip) < 1e-9
    assert np.all(drop.tip[on, 2] >= tangent.tip[:, 2] - 1e-9)


def test_bad_placement_and_step():
    with pytest.raises(ValueError, match="placement: expected one of drop, cc"):
        Planner(Roof(), parse_tools([{"diameter": 8, "corner_radius": 1}]), machine="3axis",
                placement="gouge")
    with pytest.raises(ValueError, match="fixed.step: "):
        ToolpathProblem(surface=Roof(), machine="3axis", fixed={"step": 0})
