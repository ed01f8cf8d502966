"""Zoning: features, K-means + connected zones, step-over, passes, the Eq. 4 plan, the CLI."""

import json
import subprocess
import sys

import numpy as np
import pytest
from scipy import ndimage

from evoplan.problems.toolpath import choi_surface
from evoplan.problems.toolpath.geometry.surface import PolynomialSurface
from evoplan.problems.toolpath.plan.zoning.amas import amas_zoning
from evoplan.problems.toolpath.plan.zoning.features import mesh_features
from evoplan.problems.toolpath.plan.zoning.kmeans import connected_zones, kmeans_zoning
from evoplan.problems.toolpath.plan.zoning.passes import length_lower_bound, zone_passes
from evoplan.problems.toolpath.plan.zoning.plan import plan_zones
from evoplan.problems.toolpath.plan.zoning.profile import profile_width
from evoplan.problems.toolpath.plan.zoning.samples import sample_surface
from evoplan.problems.toolpath.plan.zoning.stepover import ScallopTarget, plane_spacing

TORUS = ScallopTarget.build(3.175, 1.0, 0.254)
BALL = ScallopTarget.build(3.175, 3.175, 0.254)


def plane(slope_x=0.0, slope_y=0.0, size=(40.0, 30.0)):
    """z = slope_x x + slope_y y over [0, size] (a PolynomialSurface, u along x, v along y)."""
    a = np.zeros((2, 2, 3))
    a[1, 0] = [size[0], 0.0, slope_x * size[0]]
    a[0, 1] = [0.0, size[1], slope_y * size[1]]
    return PolynomialSurface(a, name="plane")


class TwoPlanes(PolynomialSurface):
    """A roof: z rises along x on u < 0.5 and along y on u > 0.5 (continuous at u = 0.5).

    Two planes with perpendicular slope directions, joined by a crease at x = 20 mm.
    """

    def __init__(self):
        a = np.zeros((2, 2, 3))
        a[1, 0] = [40.0, 0.0, 0.0]
        a[0, 1] = [0.0, 30.0, 0.0]
        super().__init__(a, normal_sign=1.0, name="two_planes")

    def jet(self, u, v, order=2):
        j = super().jet(u, v, order)
        left = np.asarray(u) < 0.5
        tan = np.tan(np.radians(15))
        p = j.p.copy()
        p[:, 2] = np.where(left, tan * 40 * np.asarray(u), tan * 30 * np.asarray(v) + tan * 20 - tan * 15)
        su, sv = (None if x is None else x.copy() for x in (j.su, j.sv))
        if su is not None:
            su[:, 2] = np.where(left, tan * 40, 0.0)
            sv[:, 2] = np.where(left, 0.0, tan * 30)
        zero = None if j.suu is None else np.zeros_like(j.suu)
        return type(j)(p, su, sv, zero, zero, zero)


def test_profile_matches_closed_forms():
    # ball on a plane: 2 sqrt(2 R h - h^2); torus on a horizontal plane: its cap
    assert profile_width(BALL, [0.0], [0.0], [0.0])[0] == pytest.approx(2 * np.sqrt(2 * 3.175 * 0.254 - 0.254 ** 2), rel=1e-9)
    assert profile_width(TORUS, [0.0], [0.0], [0.0])[0] == pytest.approx(TORUS.width_cap, rel=1e-6)
    # torus fed along the steepest slope of a 20 deg plane: ellipse (R-r, (R-r) sin S) + r,
    # narrower than the flat case and wider than the ball, and the circle model is wider
    s = np.radians(20)
    w = profile_width(TORUS, [np.sin(s)], [0.0], [0.0])[0]
    assert profile_width(BALL, [0.0], [0.0], [0.0])[0] < w < TORUS.width_cap
    # a convex section (kappa < 0) narrows the step, a concave one widens it
    w_cx = profile_width(BALL, [0.0], [0.0], [-0.05])[0]
    w_cc = profile_width(BALL, [0.0], [0.0], [0.05])[0]
    assert w_cx < 2.4887 < w_cc


def test_plane_spacing_prefers_the_steepest_direction_for_a_torus():
    s = sample_surface(plane(slope_x=np.tan(np.radians(20))), spacing=1.0)
    along = plane_spacing(s, TORUS, 0.0)  # feed along x = steepest
    across = plane_spacing(s, TORUS, np.pi / 2)
    assert np.all(along > 1.5 * across)
    assert np.all(plane_spacing(s, BALL, 0.0) <= BALL.width_cap + 1e-12)
    circle = plane_spacing(s, TORUS, np.pi / 2, model="circle")
    assert np.allclose(circle, circle[0]) and circle[0] < across[0]  # R_eff = r across


def test_plane_gives_one_zone_by_both_methods():
    f = mesh_features(plane(0.2, 0.1), 20, 15)
    assert np.all(kmeans_zoning(f, 1) == 0)
    assert np.all(amas_zoning(f.optimal_feed, seed=3).labels == 0)


@pytest.mark.parametrize("method", ["kmeans", "amas"])
def test_two_planes_split_into_exactly_those_two(method):
    surface = TwoPlanes()
    f = mesh_features(surface, 24, 18)
    half = (f.u < 0.5).astype(int)
    labels = (kmeans_zoning(f, 2) if method == "kmeans"
              else amas_zoning(f.optimal_feed, k_cmd=1.0, k_lz=0.15, seed=0).labels)
    assert len(np.unique(labels)) == 2
    assert np.all(labels == half) or np.all(labels == 1 - half)
    settings = {"K": 2} if method == "kmeans" else {}
    plan = plan_zones(surface, TORUS, method, mesh=(24, 18), seed=0, **settings)
    assert len(plan.zones) == 2  # the default merging keeps both planes
    dirs = sorted(round(z.direction_deg) % 180 for z in plan.zones)
    assert dirs == [0, 90]  # each plane machined along its own steepest slope


def test_zones_are_connected_after_splitting():
    rng = np.random.default_rng(0)
    clusters = rng.integers(0, 3, size=(30, 20))
    zones = connected_zones(clusters)
    assert sorted(np.unique(zones)) == list(range(zones.max() + 1))
    for z in range(zones.max() + 1):
        mask = zones == z
        assert len(np.unique(clusters[mask])) == 1
        assert ndimage.label(mask)[1] == 1
    f = mesh_features(choi_surface(), 40, 40)
    for k in range(2, 7):
        labels = kmeans_zoning(f, k)
        for z in range(labels.max() + 1):
            assert ndimage.label(labels == z)[1] == 1


@pytest.mark.parametrize("method,kw", [("single", {}), ("kmeans", {"K": 3}), ("kmeans", {"K": 5}),
                                       ("amas", {"k_lz": 0.15, "seed": 1})])
def test_total_never_below_the_lower_bounds(method, kw):
    surface = choi_surface()
    samples = sample_surface(surface, spacing=0.5)
    for cutter in (TORUS, BALL):
        plan = plan_zones(surface, cutter, method, mesh=(30, 30), samples=samples, scan=4, **kw)
        bound = sum(z.lower_bound for z in plan.zones)
        assert plan.cutting_length >= bound > 0
        assert plan.total_length == pytest.approx(plan.cutting_length + (len(plan.zones) - 1) * 40)
        for z in plan.zones:  # the optimizer never returns worse than its start
            assert z.length <= z.start_length + 1e-9


def test_passes_cover_a_plane_with_the_expected_count():
    s = sample_surface(plane(), spacing=0.25)  # 40 x 30 mm horizontal
    zp = zone_passes(s, BALL, 0.0)  # planes along x, spaced across y
    w = 2 * np.sqrt(2 * 3.175 * 0.254 - 0.254 ** 2)
    assert len(zp.s) == int(np.ceil((zp.s[-1] - zp.s[0]) / w)) + 1
    assert np.all(zp.spacing <= w + 1e-9)
    assert zp.length == pytest.approx(len(zp.s) * 40.0, rel=0.02)
    assert zp.length >= length_lower_bound(s, BALL)


def test_bad_input_is_a_clear_error():
    f = mesh_features(plane(), 3, 2)
    with pytest.raises(ValueError, match="^K: 7 zones asked from a mesh of only 6 cells"):
        kmeans_zoning(f, 7)
    with pytest.raises(ValueError, match="^mesh: a mesh needs at least 2 cells"):
        mesh_features(plane(), 1, 1)
    with pytest.raises(ValueError, match="^mesh: a mesh needs at least 2 cells"):
        mesh_features(plane(), 0, 5)
    with pytest.raises(ValueError, match="^cutter.r: the corner radius"):
        ScallopTarget.build(3.0, 4.0, 0.1)


def run_cli(args):
    proc = subprocess.run([sys.executable, "-m", "evoplan", *map(str, args)], capture_output=True,
                          text=True, timeout=300, env={**__import__("os").environ, "MPLBACKEND": "Agg"})
    return proc.returncode, proc.stdout, proc.stderr


def test_zone_cli_writes_everything_or_nothing(tmp_path):
    cfg = tmp_path / "z.yaml"
    cfg.write_text("surface: choi\nmesh: [20, 20]\nmethod: kmeans\nkmeans: {K: 3}\n"
                   "sample_spacing: 0.5\ndirection_scan: 4\n")
    out = tmp_path / "out"
    code, stdout, stderr = run_cli(["zone", str(cfg), "--out", str(out)])
    assert code == 0, stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["n_zones"] == len(summary["zones"]) >= 3
    assert summary["total_length_mm"] == pytest.approx(
        sum(z["length_mm"] for z in summary["zones"]) + summary["penalty_mm"], abs=0.01)
    rows = (out / "zones.csv").read_text().splitlines()
    assert len(rows) == 1 + 400
    assert (out / "zone_map.png").read_bytes()[:4] == b"\x89PNG"
    for bad, msg in [("kmeans: {K: 500}", "K: 500 zones asked from a mesh of only 400 cells"),
                     ("method: amas\namas: {k_lz: 1.5}", "k_lz: must be in [0, 1]"),
                     ("method: amas\namas: {k_cmd: -0.1}", "k_cmd: must be in [0, 1]"),
                     ("mesh: [1, 1]", "mesh: a mesh needs at least 2 cells")]:
        base = "".join(line for line in ("mesh: [20, 20]\n", "method: kmeans\n") if line.split(":")[0] not in bad)
        cfg.write_text("surface: choi\n" + base + bad + "\n")  # duplicate keys are refused
        out2 = tmp_path / "bad"
        code, stdout, stderr = run_cli(["zone", str(cfg), "--out", str(out2)])
        assert code == 2 and msg in stderr and "Traceback" not in stderr
        assert stderr.count("\n") == 1
        assert not out2.exists()


def test_zoning_genes_in_the_toolpath_problem():
    from evoplan.problems.toolpath import ToolpathProblem
    from tests.choi_zoning import choi_zoning

    prob = ToolpathProblem(**choi_zoning(mesh=(30, 30), gene_range=(1, 4)))
    assert list(prob.variables) == ["tool", "zones"]
    X = np.array([[0, 1], [1, 1], [1, 2]], float)  # ball 1 zone, torus 1 zone, torus K=2
    c = prob.criteria(X)
    assert c["zones"][0] == c["zones"][1] == 1 and c["zones"][2] >= 2
    assert np.allclose(c["eq4_total"], c["cutting_length"] + (c["zones"] - 1) * 40.0)
    out = {}
    prob._evaluate(X, out)
    assert np.allclose(out["F"][:, 0], c["eq4_total"])
    assert c["eq4_total"][2] < c["eq4_total"][1]  # zoning pays off for the torus
    with pytest.raises(ValueError, match="^ranges.zones: expected integers in \\[1, 400\\]"):
        ToolpathProblem(**choi_zoning(mesh=(20, 20), gene_range=(1, 401)))
    with pytest.raises(ValueError, match="^ranges.k_lz: the range must lie in \\[0, 1\\]"):
        ToolpathProblem(**choi_zoning(mesh=(20, 20), method="amas", gene_range=(0.1, 1.5)))
