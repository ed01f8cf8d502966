"""Roughing a trimmed face: the block covers the face's XY box; off the face's footprint (the
sample STEP part's drilled hole and side notch) the floor is the face's continuation, the
surface the semi-finish's ball follows there too, and the stock left is measured on the part."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

from evoplan.problems.toolpath.cutters import make_cutter  # noqa: E402
from evoplan.problems.toolpath.export.toolpath import Tool  # noqa: E402
from evoplan.problems.toolpath.geometry.spec import parse_surface  # noqa: E402
from evoplan.problems.toolpath.roughing.operations import block_stock, roughing  # noqa: E402
from evoplan.problems.toolpath.roughing.zmap import StockZMap  # noqa: E402

RUNS = Path(__file__).resolve().parents[3] / "runs"
HOLE, NOTCH, FACE = (65.0, 40.0), (10.0, 40.0), (50.0, 20.0)  # make_step_part.py's hole and notch
A = 0.8  # semi-finish + finish allowance


@pytest.fixture(scope="module")
def roughed():
    """The roughing of runs/step_block_machine.yaml (zlevel, flat D12, 3 mm deep, 60 % of D)."""
    surface = parse_surface({"type": "step", "file": "parts/sculpted_block.step", "face": "largest"},
                            "surface", RUNS)
    stock = block_stock(surface, 1.0, top_offset=3.0)
    tool = Tool(1, make_cutter(12.0, 0.0), 6000)
    tp, stats, _ = roughing(stock, "zlevel", tool, d_cut=3.0, stepover=0.6 * 12.0, allowance_semi=0.5,
                            allowance_finish=0.3, feed=800, plunge_feed=250)
    zmap = StockZMap(stock.grid, stock.z_top)
    zmap.cut(tp)
    return stock, stats, zmap


def test_the_hole_and_the_notch_are_off_the_part(roughed):
    stock, _, _ = roughed
    at = {name: stock.part[stock.grid.index(*xy)] for name, xy in
          {"hole": HOLE, "notch": NOTCH, "face": FACE}.items()}
    assert at == {"hole": False, "notch": False, "face": True}
    # the hole (r 8 mm) and the notch (30 x 20 mm) are about 200 + 600 of the 8080 cells
    assert 700 < int((~stock.part).sum()) < 1000


def test_off_the_part_the_block_is_roughed_to_the_faces_continuation(roughed):
    stock, _, zmap = roughed
    for xy in (HOLE, NOTCH):
        r, c = stock.grid.index(*xy)
        z = stock.z_surface[r, c]  # the untrimmed face's height there (finite: the continuation)
        assert np.isfinite(z) and z + A - 0.02 <= zmap.h[r, c] < stock.z_top - 1.0


def test_the_stock_left_is_measured_on_the_part(roughed):
    stock, stats, zmap = roughed
    on_part = zmap.clearance_over(stock.z_surface, stock.part)
    assert (stats["left_min"], stats["left_max"]) == on_part
    assert stats["left_min"] >= A - 0.02
    # the hole drilled to the continuation's height: nothing left there, yet the part keeps its
    # allowance; the whole box would report 0 mm left
    drilled = copy.deepcopy(zmap)
    hole = ~stock.part & np.isfinite(stock.z_surface)
    drilled.h[hole] = stock.z_surface[hole]
    assert drilled.clearance_over(stock.z_surface, stock.part) == on_part
    assert drilled.clearance_over(stock.z_surface)[0] == 0.0
