"""The cut simulation against closed forms: cusps of ball, flat-end with lead and torus
passes on planes, and of a ball on convex and concave cylinders (circle intersections)."""

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.clpath import CLPath
from evoplan.problems.toolpath.simulation import analytic_grid, simulate, sweep_path
from evoplan.problems.toolpath.simulation.kernel import MISS, ray_entry

H = 0.05


def _plane_grid(width=40.0, depth=30.0):
    return analytic_grid(lambda x, y: 0 * x, lambda x, y: (0 * x, 0 * x), (0, width, 0, depth), H)


def _passes(ys, z_of_y, axis_of_y, x0=-6.0, x1=46.0, n=27, one_way=False):
    """Straight passes along x at the given y: tips (x, y, z(y)), one section per pass when
    one_way, else zig-zag in one section."""
    tips, axes, sec = [], [], []
    for k, y in enumerate(ys):
        xs = np.linspace(x0, x1, n)
        if k % 2 and not one_way:
            xs = xs[::-1]
        tips += [(x, *z_of_y(y)) for x in xs]
        axes += [axis_of_y(y)] * n
        sec += [k if one_way else 0] * n
    return np.array(tips), np.array(axes), np.array(sec)


def _row(grid, y):
    i = int(round((y - grid.y0) / grid.h))
    assert abs(grid.y0 + i * grid.h - y) < 1e-9, "the check row must sit on cell centres"
    return i


def test_ray_entry_ball_torus_flat_vertical():
    # vertical ray under a vertical cutter at radial distance rho: the lower profile height
    for R, r in ((4.0, 4.0), (8.0, 3.0), (6.0, 0.0)):
        for rho in (0.0, 1.0, R - r + 0.5 * r, R - 1e-3):
            want = 0.0 if rho <= R - r else r - np.sqrt(r * r - (rho - R + r) ** 2)
            got = ray_entry(rho, 0.0, -5.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, make_cutter(2 * R, r).kernel_params())
            assert got - 5.0 == pytest.approx(want, abs=1e-9)
        # a miss scores MISS plus how far outside the radius the ray passes
        miss = ray_entry(R + 0.01, 0.0, -5.0, 0.0, 0.0, 1.0, 0, 0, 0, 0, 0, 1.0, make_cutter(2 * R, r).kernel_params())
        assert miss == pytest.approx(MISS + 0.01)


@pytest.mark.parametrize("s", [1.0, 2.0, 3.0])
def test_ball_on_plane_cusp(s):
    R = 4.0
    g = _plane_grid()
    ys = 5.025 + s * np.arange(int(20 / s) + 1)
    tips, axes, sec = _passes(ys, lambda y: (y, 0.0), lambda y: (0, 0, 1))
    res = sweep_path(CLPath(tips, axes, make_cutter(2 * R, R), section=sec), g).values
    cusp = res[_row(g, ys[2] + s / 2), 100:700]
    assert cusp.max() == pytest.approx(R - np.sqrt(R * R - s * s / 4), abs=2e-5)
    assert np.ptp(cusp) < 2e-5  # the same all along the pass
    on = res[_row(g, ys[2]), 100:700]
    # the ball touches the plane under its pass (no gouge), to the search's tolerance (1e-5 mm)
    assert np.abs(on).max() < 1e-5


def test_flat_end_with_lead_on_plane_leaves_an_ellipse():
    # one-way passes of a flat-end mill leaning by the lead angle along the feed: the swept
    # profile across the feed is an ellipse with semi-axes R and R sin(lead)
    R, lead, s = 6.0, np.radians(3.0), 6.0
    a = (np.sin(lead), 0.0, np.cos(lead))
    # the lowest rim point (toe) must touch z = 0: tip z = R sin(lead)
    g = _plane_grid()
    ys = 5.025 + s * np.arange(4)
    tips, axes, sec = _passes(ys, lambda y: (y, R * np.sin(lead)), lambda y: a, one_way=True)
    res = sweep_path(CLPath(tips, axes, make_cutter(2 * R, 0.0), section=sec), g).values
    for frac in (0.5, 0.3):
        y = ys[1] + frac * s
        i = _row(g, np.round((y - g.y0) / H) * H + g.y0)
        yc = g.y0 + i * H
        d = min(abs(yc - ys[1]), abs(yc - ys[2]))
        want = R * np.sin(lead) * (1 - np.sqrt(1 - (d / R) ** 2))
        assert res[i, 100:600].max() == pytest.approx(want, abs=5e-5)


def test_torus_on_plane_cusp():
    R, r, s = 4.0, 1.0, 7.0
    g = _plane_grid()
    ys = 5.025 + s * np.arange(3)
    tips, axes, sec = _passes(ys, lambda y: (y, 0.0), lambda y: (0, 0, 1))
    res = sweep_path(CLPath(tips, axes, make_cutter(2 * R, r), section=sec), g).values
    want = r - np.sqrt(r * r - (s / 2 - (R - r)) ** 2)
    assert res[_row(g, ys[0] + s / 2), 100:700].max() == pytest.approx(want, abs=2e-5)
    # within the flat bottom's width nothing is left
    assert np.abs(res[_row(g, ys[0] + 2.0), 100:700]).max() < 1e-9


@pytest.mark.parametrize("convex", [True, False])
def test_ball_on_cylinder_cusp(convex):
    rho, R, dphi = 30.0, 4.0, np.radians(8.0)
    if convex:  # z = sqrt(rho^2 - y^2), axis along x at z = 0
        fz = lambda x, y: np.sqrt(rho * rho - y * y) + 0 * x
        fg = lambda x, y: (0 * x, -y / np.sqrt(rho * rho - y * y))
    else:  # a trough z = rho - sqrt(rho^2 - y^2), axis along x at z = rho
        fz = lambda x, y: rho - np.sqrt(rho * rho - y * y) + 0 * x
        fg = lambda x, y: (0 * x, y / np.sqrt(rho * rho - y * y))
    g = analytic_grid(fz, fg, (0, 40, -12, 12), H)
    y_mid = g.y0 + _row(g, g.y0 + 240 * H) * H  # a cell-centre row near y = 0
    phi_mid = np.arcsin(y_mid / rho)
    phis = phi_mid + dphi * (np.arange(-2, 3) + 0.5)
    D = rho + R if convex else rho - R
    ax_z = 0.0 if convex else rho

    def tip(phi):  # the ball centre on the offset cylinder, the tip R below it (3-axis)
        sgn = 1.0 if convex else -1.0
        return D * np.sin(phi), ax_z + sgn * D * np.cos(phi) - R

    ys = [rho * np.sin(p) for p in phis]
    by_y = dict(zip(ys, phis))
    tips, axes, sec = _passes(ys, lambda y: tip(by_y[y]), lambda y: (0, 0, 1), x0=-6, x1=46)
    res = sweep_path(CLPath(tips, axes, make_cutter(2 * R, R), section=sec), g).values
    # cusp: the intersection of the two ball spheres on the bisecting normal
    disc = np.sqrt(R * R - (D * np.sin(dphi / 2)) ** 2)
    if convex:
        want = D * np.cos(dphi / 2) - disc - rho
    else:
        want = rho - (D * np.cos(dphi / 2) + disc)
    got = res[_row(g, y_mid), 100:700]
    assert got.max() == pytest.approx(want, rel=2e-3, abs=2e-5)


def test_metrics_of_a_plane_cut():
    R, s = 4.0, 2.0
    g = _plane_grid()
    ys = 5.025 + s * np.arange(11)
    tips, axes, sec = _passes(ys, lambda y: (y, 0.0), lambda y: (0, 0, 1))
    sim = simulate(CLPath(tips, axes, make_cutter(2 * R, R), section=sec), g, allowance=0.5)
    m = sim.metrics
    assert m["gouge_max_mm"] < 1e-6 and m["gouge_area_mm2"] == 0
    # beside the outer passes the ball's side rises above the allowance a at a lateral
    # distance sqrt(R^2 - (R - a)^2): those cells keep their stock
    reach = np.sqrt(R * R - (R - 0.5) ** 2)
    y = g.y0 + H * np.arange(g.shape[0])
    uncut = (y < ys[0] - reach) | (y > ys[-1] + reach)
    assert m["uncut_fraction"] == pytest.approx(uncut.mean(), abs=2 * H / 30)
    assert m["scallop_max_mm"] == 0.5  # uncut cells keep the allowance



def test_vertical_rays_measure_the_same_cusp_stretched_by_the_slope():
    # a plane rising along y (z = 0.5 y), ball passes along x spaced s on the surface with the
    # axis on the normal: the cusp along the normal is the flat closed form, and measured
    # vertically it is longer by 1 / n_z (the cut surface is parallel to the design surface)
    R, s, slope = 4.0, 2.5, 0.5
    nz = 1.0 / np.sqrt(1.0 + slope * slope)
    n = np.array([0.0, -slope, 1.0]) * nz
    g = analytic_grid(lambda x, y: slope * y + 0 * x, lambda x, y: (0 * x, slope + 0 * x),
                      (0, 40, 0, 30), H)
    ys = 5.0 + s * nz * np.arange(8)  # XY spacing of the passes: s on the surface

    def tip(y):  # ball centre R along the normal from the CC point, the tip R below it on the axis
        c = np.array([0.0, y, slope * y]) + R * n
        return (c - R * n)[1:]

    tips, axes, sec = _passes(ys, tip, lambda y: tuple(n))
    path = CLPath(tips, axes, make_cutter(2 * R, R), section=sec)
    normal = sweep_path(path, g).values[:, 100:700]
    vertical = sweep_path(path, g, vertical=True).values[:, 100:700]
    band = (g.ys[:, None] > ys[1]) & (g.ys[:, None] < ys[-2]) & np.ones_like(normal, bool)
    want = R - np.sqrt(R * R - s * s / 4)
    assert normal[band].max() == pytest.approx(want, rel=0.02)
    assert vertical[band].max() == pytest.approx(want / nz, rel=0.02)
