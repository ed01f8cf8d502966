"""The users of the cutter abstraction: the tool database hands out cutters, the analytic
criteria's undercut and the NC outputs (label, APT CUTTER/) go through the cutter's shape."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.cutters import BallEndCutter, FlatEndCutter, ToroidalCutter
from evoplan.problems.toolpath.export.apt_write import header
from evoplan.problems.toolpath.export.toolpath import Tool
from evoplan.problems.toolpath.spec import parse_tools


def test_the_database_hands_out_the_inferred_cutters():
    db = parse_tools([{"diameter": 8, "corner_radius": 0}, {"diameter": 12, "corner_radius": 2,
                      "type": "bull-nose"}, {"diameter": 16, "type": "ball"}])
    assert [type(c) for c in db.cutters] == [FlatEndCutter, ToroidalCutter, BallEndCutter]
    assert [t.type for t in db.tools] == ["flat", "toroidal", "ball"]  # aliases -> the kind
    assert db.cutter(2).corner_radius == 8.0 and db.tools[2].corner_radius == 8.0
    assert np.array_equal(db.R, [4.0, 6.0, 8.0]) and not hasattr(db, "r")
    assert [c.corner_radius for c in db.cutters] == [0.0, 2.0, 8.0]
    assert [c.sharp_rim for c in db.cutters] == [True, False, False]
    with pytest.raises(ValueError, match=r"tools\[0\].type: 'flat' does not match D 8, r 1"):
        parse_tools([{"diameter": 8, "corner_radius": 1, "type": "flat"}])
    with pytest.raises(ValueError, match=r"tools\[0\].type: expected one of"):
        parse_tools([{"diameter": 8, "corner_radius": 1, "type": ["flat"]}])


def test_only_a_sharp_rim_reports_an_undercut():
    """Tilted across the feed on a plane, the flat-end's rim leaves material (its undercut);
    the same orientation gives no undercut for the toroidal and ball tools."""
    from engine_rows import criteria
    from toolpath_analytic import Plane

    db = parse_tools([{"diameter": 12, "corner_radius": 0}, {"diameter": 12, "corner_radius": 2},
                      {"diameter": 12, "corner_radius": 6}])
    X = np.array([[i, 40.0, 0.0, 3.0, 5.0] for i in range(3)])
    crit = criteria(Plane(0.0, 100.0, 0.0, 60.0), db, X)
    assert crit["undercut_max"][0] == crit["scallop_max"][0] > 0.01
    assert np.all(crit["undercut_max"][1:] == 0.0) and np.all(crit["scallop_max"][1:] > 0)


def test_nc_outputs_take_the_shape_from_the_cutter():
    assert [Tool(1, make_cutter(8, 0)).label(), Tool(1, make_cutter(12, 6)).label(), Tool(1, make_cutter(16, 3)).label()] == [
        "flat D8", "ball D12", "toroidal D16 r3"]
    assert "CUTTER/16.0000,3.0000" in header(cutter=make_cutter(16, 3))
    with pytest.raises(ValueError, match=r"tool.corner_radius: must be in \[0, D/2 = 4\]"):
        header(cutter=make_cutter(8, 5, key="tool"))


@pytest.mark.parametrize("r", [0.0, 1.0, 3.175])
@pytest.mark.parametrize("slope_deg", [0.0, 20.0])
def test_the_3axis_and_5axis_silhouettes_agree_with_the_closed_form(r, slope_deg):
    """One silhouette, two users: a vertical cutter fed straight up a plane of slope S is the
    5-axis case lead = S, tilt = 0. At a height h above the contact, the 3-axis side width
    (zoning) and the 5-axis profile table (analytic scallop) give the same lateral offset, and on
    horizontal ground it is the cutter's own width(h) = R0 + sqrt(2 r h - h^2)."""
    from evoplan.problems.toolpath.cutters import make_cutter
    from evoplan.problems.toolpath.cutters.silhouette import profile_tables, side_width_exact

    R, S = 3.175, np.radians(slope_deg)
    h = np.array([0.02, 0.1, 0.254, 0.6])
    side3 = side_width_exact(R, r, h, np.sin(S), 0.0)
    x, z, _ = profile_tables(np.array([R]), np.array([r]), np.array([S]), np.zeros(1))
    side5 = np.interp(h, z[0], x[0])  # +b row; z rises with x
    if r > 0 or S > 0:  # a flat-end flat on the ground has no rising side to interpolate
        assert np.allclose(side3, side5, atol=1e-3)  # the table is sampled: ~3e-4
    if S == 0:
        assert np.allclose(side3, make_cutter(2 * R, r).width(h), atol=1e-9)


@pytest.mark.parametrize("d, r", [(8.0, 0.0), (8.0, 1.0), (8.0, 4.0)])
def test_the_centre_is_the_corner_arcs_centre_and_centre_points_read_back_as_tips(d, r):
    """The lower profile's corner arc is the circle of radius r about the point centre_height
    above the tip, R0 = R - r off the axis (the ball's centre for a ball-end); a CL file
    written at the centre reads back at the tips."""
    from evoplan.problems.toolpath.clpath import CLPath
    from evoplan.problems.toolpath.cutters import make_cutter

    c = make_cutter(d, r)
    r0 = d / 2 - r
    rho = np.linspace(r0, d / 2, 50)
    assert np.allclose((rho - r0) ** 2 + (c.height(rho) - c.centre_height) ** 2, r * r)
    assert np.all(c.height(np.linspace(0.0, r0, 20)) == 0.0)
    rng = np.random.default_rng(3)
    tip = rng.normal(size=(5, 3))
    axis = rng.normal(size=(5, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)

    class Apt:  # what export.apt_read.read_apt gives, reduced to what CLPath reads
        cutter, tip_is_centre = c, True
        rapid = np.zeros(5, bool)
        feed = np.full(5, 800.0)
        section = np.zeros(5, int)

    Apt.tip, Apt.axis = tip + c.centre_height * axis, axis
    path = CLPath.from_apt(Apt)
    assert np.allclose(path.tip, tip, atol=1e-12) and path.cutter == c


def test_a_mixed_batch_gives_each_row_its_own_cutters_profile():
    """The analytic criteria ask each tool's cutter for the profiles of its rows and put them
    back in row order: a batch mixing tools gives every row what it gives alone (to
    round-off)."""
    from engine_rows import criteria

    from evoplan.problems.toolpath import fountas_surface

    surface, db = fountas_surface(), parse_tools()
    rng = np.random.default_rng(5)
    X = np.column_stack([[5, 0, 8, 5, 3, 6, 0], rng.uniform(20, 45, 7), rng.uniform(0, 8, 7),
                         rng.uniform(0, 8, 7), rng.uniform(2, 8, 7)])
    batch = criteria(surface, db, X)
    for i, x in enumerate(X):
        alone = criteria(surface, db, x[None, :])
        for name in ("scallop_max", "scallop_mean", "gouge_max", "undercut_max"):
            assert batch[name][i] == pytest.approx(alone[name][0], rel=1e-9, abs=1e-12), (name, i)
