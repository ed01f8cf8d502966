"""Cell areas clipped to the part (``simulation/clip.py``): a cell that straddles the
footprint's edge weighs only its inside part, and the areas add up to the part's."""

import numpy as np

from evoplan.problems.toolpath.geometry.bezier import choi_surface
from evoplan.problems.toolpath.geometry.surface import PolynomialSurface
from evoplan.problems.toolpath.simulation import design_grid


def _tilted_parallelogram():
    """S(u, v) = P0 + u A + v B: a plane over an oblique parallelogram, area |A x B|."""
    p0, a, b = np.array([1.3, -2.1, 5.0]), np.array([37.0, 11.0, 9.0]), np.array([-8.0, 23.0, 4.0])
    coeffs = np.zeros((2, 2, 3))
    coeffs[0, 0], coeffs[1, 0], coeffs[0, 1] = p0, a, b
    return PolynomialSurface(coeffs), float(np.linalg.norm(np.cross(a, b)))


def _gauss_area(surface, n=48):
    g, w = np.polynomial.legendre.leggauss(n)
    g, w = 0.5 * (g + 1), 0.5 * w
    u, v = (x.ravel() for x in np.meshgrid(g, g, indexing="ij"))
    j = surface.jet(u, v, order=1)
    return float((np.linalg.norm(np.cross(j.su, j.sv), axis=1) * np.outer(w, w).ravel()).sum())


def test_clipped_areas_sum_to_a_planes_area_exactly():
    surface, area = _tilted_parallelogram()
    for h in (0.37, 0.8):
        grid = design_grid(surface, h)
        clipped = grid.cell_area().sum()
        whole = np.where(grid.inside, h * h / np.abs(grid.normal[..., 2]), 0.0).sum()
        assert abs(clipped / area - 1) < 1e-6
        assert abs(whole / area - 1) > 1e-4  # whole cells miscount an oblique edge


def test_clipped_areas_sum_to_chois_area():
    surface = choi_surface()
    grid = design_grid(surface, 0.1)
    area = _gauss_area(surface)
    assert abs(grid.cell_area().sum() / area - 1) < 1e-6
    # no cell carries more than its own square plus the slivers of its neighbours
    assert grid.weight.max() <= 3.0 + 1e-9 and grid.weight[grid.inside].min() > 0


def test_meets_h_c_verdict_and_flips():
    from evoplan.problems.toolpath.simulation.metrics import meets_h_c, verdicts

    good = {"scallop_p99_mm": 0.24, "scallop_max_mm": 0.27, "uncut_fraction": 0.0,
            "gouge_max_mm": 0.004}
    assert meets_h_c(good, 0.254, 0.01) == (True, [])
    for key, value, word in (("scallop_p99_mm", 0.254, "p99"), ("scallop_max_mm", 0.28, "max"),
                             ("uncut_fraction", 1e-6, "uncut"), ("gouge_max_mm", 0.011, "gouge")):
        ok, why = meets_h_c({**good, key: value}, 0.254, 0.01)
        assert not ok and len(why) == 1 and why[0].startswith(word)
    v = verdicts({0.2: good, 0.1: good, 0.05: {**good, "scallop_max_mm": 0.303}}, 0.254, 0.01)
    assert v["final"] is False and v["flip"] is True and v["by_grid"][0.2][0] is True
    v = verdicts({0.2: {**good, "scallop_max_mm": 0.3}, 0.1: good, 0.05: good}, 0.254, 0.01)
    assert v["final"] is True and v["flip"] is False


def test_clipped_areas_follow_a_curved_footprint():
    # x = 30 u + 9 v^2, y = 20 v + 6 u^2, z = 3 u + 2 v: the (u, v) square's edges are
    # parabolas in XY, so a footprint of the square's corners alone would be wrong
    coeffs = np.zeros((3, 3, 3))
    coeffs[1, 0] = (30.0, 0.0, 3.0)
    coeffs[0, 1] = (0.0, 20.0, 2.0)
    coeffs[0, 2, 0], coeffs[2, 0, 1] = 9.0, 6.0
    surface = PolynomialSurface(coeffs)
    grid = design_grid(surface, 0.25)
    assert abs(grid.cell_area().sum() / _gauss_area(surface) - 1) < 1e-4
