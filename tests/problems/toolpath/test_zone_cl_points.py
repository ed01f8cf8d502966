"""CL points of a zoning plan: sections on the planes, zone cells, zig-zag, placements."""

import numpy as np
import pytest
from scipy.spatial import cKDTree
from toolpath_analytic import GraphSurface

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.plan.zoning.cl_points import zone_cl_path
from evoplan.problems.toolpath.plan.zoning.features import mesh_features
from evoplan.problems.toolpath.plan.zoning.passes import ZonePasses
from evoplan.problems.toolpath.plan.zoning.plan import ZonePlan, ZoningPlan, plan_from_labels
from evoplan.problems.toolpath.plan.zoning.samples import sample_surface
from evoplan.problems.toolpath.plan.zoning.stepover import ScallopTarget

SLOPE = 0.4


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


def _labels(n=20, m=12):
    lab = np.zeros((n, m), np.int64)
    lab[n // 2:] = 1  # the ridge x = 50 is the cell border u = 0.5
    return lab


def _hand_plan():
    """Zone 0 (x < 50) fed along +x (its slope) on planes y = s; zone 1 fed along y on
    planes x = -s (alpha = 90 deg: c = (-1, 0))."""
    s0 = np.arange(5.0, 56.0, 7.0)
    s1 = -np.arange(55.0, 96.0, 8.0)
    zones = [ZonePlan(z, 120, 3000.0, 0.0, np.degrees(a), 0.0,
                      ZonePasses(a, s, np.full(len(s), 50.0), np.diff(s)), 0.0, 0)
             for z, a, s in ((0, 0.0, s0), (1, np.pi / 2, s1))]
    return ZoningPlan("single", _labels(), zones, 0.0, {})


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


@pytest.mark.parametrize("d, r", [(8.0, 0.0), (8.0, 1.0), (8.0, 4.0)])
def test_hand_plan_points_lie_on_their_planes_zones_and_closed_form_tips(d, r):
    surface, plan, cutter = Roof(), _hand_plan(), make_cutter(d, r)
    path = zone_cl_path(surface, plan, cutter, step=1.0, placement="cc")
    cc, uv = path.info["cc"], path.info["uv"]
    lab = plan.labels
    cell_zone = lab[np.minimum((uv[:, 0] * 20).astype(int), 19), np.minimum((uv[:, 1] * 12).astype(int), 11)]
    assert np.array_equal(cell_zone, path.zone)
    assert np.allclose(cc[:, 2], 20.0 - SLOPE * np.abs(cc[:, 0] - 50.0), atol=1e-9)
    for z, zp in enumerate(plan.zones):
        a = zp.passes.alpha
        f, c = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
        passes = np.unique(path.pass_index[path.zone == z])
        assert len(passes) == len(zp.passes.s)  # one section per plane: no empty pass
        travel = []
        for k, s in zip(passes, zp.passes.s):
            pts = cc[path.pass_index == k]
            assert np.allclose(pts[:, :2] @ c, s, atol=1e-9)  # on its plane
            t = pts[:, :2] @ f
            dt = np.diff(t)
            assert np.all(np.abs(dt) <= 1.0 + 1e-9) and np.allclose(dt, dt[0])  # <= step, even
            lo, hi = (0.0, 50.0) if z == 0 else (0.0, 60.0)
            assert np.isclose(t.min(), lo, atol=1e-6) and np.isclose(t.max(), hi, atol=1e-6)
            travel.append(np.sign(dt[0]))
        assert np.all(np.array(travel[1:]) == -np.array(travel[:-1]))  # zig-zag
    assert path.section.max() + 1 == len(np.unique(path.pass_index))
    side = np.where(path.zone == 0, 1.0, -1.0)
    expect = _plane_tip_z(path.tip[:, 0], path.tip[:, 1], side, cutter)
    assert np.allclose(path.tip[:, 2], expect, atol=1e-9)  # tangent to its own plane
    assert path.diameter == d and path.corner_radius == r
    assert np.allclose(path.axis, [0, 0, 1])
    assert np.isclose(path.feed_length(), sum(path.info["section_length"]), rtol=1e-12)


@pytest.mark.parametrize("d, r", [(8.0, 0.0), (8.0, 1.0), (8.0, 4.0)])
def test_drop_placement_is_the_plane_closed_form_away_from_the_ridge_and_never_gouges(d, r):
    surface, plan, cutter = Roof(), _hand_plan(), make_cutter(d, r)
    path = zone_cl_path(surface, plan, cutter, step=2.0, placement="drop")
    cc = path.info["cc"]
    assert np.allclose(path.tip[:, :2], cc[:, :2])  # dropped at the CC point's XY
    side = np.where(cc[:, 0] < 50, 1.0, -1.0)
    plane = _plane_tip_z(cc[:, 0], cc[:, 1], side, cutter)
    far = np.abs(cc[:, 0] - 50) > d / 2 + 1e-9
    assert far.sum() > 50 and (~far).sum() > 5
    assert np.allclose(path.tip[far, 2], plane[far], atol=1e-9)
    assert np.all(path.tip[~far, 2] <= plane[~far] + 1e-9)  # the ridge falls away
    assert _max_penetration(surface, cutter, path.tip) < 1e-9


def test_cc_placement_gouges_a_valley_and_the_drop_does_not():
    surface = Roof(sign=-1.0)
    n, m = 20, 12
    labels = _labels(n, m)
    zones, _ = plan_from_labels(sample_surface(surface, spacing=0.5), mesh_features(surface, n, m),
                                labels, ScallopTarget.build(4.0, 1.0, 0.2))
    plan = ZoningPlan("single", labels, zones, 0.0, {})
    cutter = make_cutter(8.0, 1.0)
    # (no chord tolerance: both placements on the same CC points)
    cc_path = zone_cl_path(surface, plan, cutter, step=2.0, placement="cc", tolerance=None)
    drop_path = zone_cl_path(surface, plan, cutter, step=2.0, placement="drop", tolerance=None)
    assert np.array_equal(cc_path.info["cc"], drop_path.info["cc"])
    uv = cc_path.info["uv"]
    cell_zone = labels[np.minimum((uv[:, 0] * n).astype(int), n - 1),
                       np.minimum((uv[:, 1] * m).astype(int), m - 1)]
    assert np.array_equal(cell_zone, cc_path.zone) and set(cc_path.zone) == {0, 1}
    for zp in zones:  # every CC point of a zone on one of its planes
        a = zp.passes.alpha
        off = cc_path.info["cc"][cc_path.zone == zp.zone, :2] @ [-np.sin(a), np.cos(a)]
        # (to the inverse map's 1e-7 mm where a stretch ends on the footprint's edge)
        assert np.abs(off[:, None] - zp.passes.s[None]).min(axis=1).max() < 1e-6
    # tangent at the CC point, the torus cuts into the other flank near the valley floor
    assert _max_penetration(surface, cutter, cc_path.tip) > 0.1
    assert _max_penetration(surface, cutter, drop_path.tip) < 1e-9
    assert np.all(drop_path.tip[:, 2] >= cc_path.tip[:, 2] - 1e-9)
    assert np.isclose(drop_path.feed_length(), sum(drop_path.info["section_length"]), rtol=0.05)


def test_bad_placement_and_step():
    with pytest.raises(ValueError, match="placement: expected one of cc, drop"):
        zone_cl_path(Roof(), _hand_plan(), make_cutter(8, 1), placement="gouge")
    with pytest.raises(ValueError, match="step: must be a number > 0"):
        zone_cl_path(Roof(), _hand_plan(), make_cutter(8, 1), step=0)
