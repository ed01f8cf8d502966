"""Result files of a zoned ``toolpath`` run (3-axis, K-means: the former ``toolpath_zoning``):
zone map, CC pattern, APT file with a section per pass of each zone; the APT file is the plan
``evoplan simulate --run`` cuts."""

from __future__ import annotations

import json

import numpy as np
import pytest

from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.cli import main
from evoplan.problems.toolpath.clpath import CLPath
from evoplan.problems.toolpath.export.apt_read import read_apt
from evoplan.problems.toolpath.export.apt_write import apt_toolpath
from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath
from evoplan.problems.toolpath.plan.zoning.figures import border_segments
from evoplan.runner import prepare_file
from tests.test_cli import evoplan, write

ZONED_RUN = """
seed: 1
problem:
  name: toolpath
  params:
    surface: choi
    tools: [{id: 1, type: ball, diameter: 6.35}, {id: 2, type: toroidal, diameter: 6.35, corner_radius: 1},
            {id: 4, type: flat, diameter: 6.35}]
    machine: 3axis
    spacing: scallop
    feed_angle: optimized
    zoning: {method: kmeans, mesh: [20, 20], merge: false}
    ranges: {zones: [3, 4]}
    fixed: {step: 1}
    weights: {eq4_total: 1}
    normalization: {eq4_total: [0, 1]}
algorithm: {name: vega, population: 4, virus: {count: 1}}
termination: {generations: 2}
"""


@pytest.fixture(scope="module")
def zoned_run(tmp_path_factory):
    """(results folder, the best plan's CLPath as the problem makes it, best.json)."""
    tmp = tmp_path_factory.mktemp("zoned")
    out = tmp / "res"
    proc = evoplan("run", write(tmp / "z.yaml", ZONED_RUN), "--out", out)
    assert proc.returncode == 0, proc.stderr
    assert "warning" not in proc.stderr, proc.stderr
    best = json.loads((out / "best.json").read_text())
    problem = prepare_file(str(out / "config.yaml")).evaluator.problem
    path, _ = problem.cl_path(best["variables"])
    return out, path, best


def test_the_run_writes_zone_map_cc_pattern_and_apt(zoned_run):
    out, path, best = zoned_run
    for name in ("zone_map.png", "cc_pattern.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG", name
    lines = (out / "toolpath.apt").read_text().splitlines()
    assert lines[0].startswith("PARTNO/") and lines[-1] == "FINI" and "TLAXIS/0,0,1" in lines
    assert max(len(line) for line in lines) <= 72
    assert f"LOADTL/{best['variables']['tool']}" in lines


def test_the_apt_file_reads_back_as_the_plan_with_a_section_per_zone_pass(zoned_run):
    out, path, best = zoned_run
    apt = read_apt(out / "toolpath.apt")
    cut = ~apt.rapid
    # every CL point of the plan, in order, and nothing else is cut to (rapids in the air aside)
    assert cut.sum() == len(path)
    assert np.abs(apt.tip[cut] - path.tip).max() <= 5e-5 + 1e-9
    starts = np.flatnonzero(np.r_[True, np.diff(path.section) != 0])
    assert len(apt.sections) == len(starts) == len(np.unique(path.section))
    assert list(apt.sections) == [f"ZONE {path.zone[i]} PASS {path.pass_index[i]}" for i in starts]
    assert np.array_equal(apt.section[cut], path.section)
    zones = {s.split()[1] for s in apt.sections}
    assert zones == {str(z) for z in np.unique(path.zone)} and len(zones) >= 3
    # the cutter is the best tool's; sections are joined by rapids only: the feed moves are the
    # plan's own plus one 1 mm plunge per section
    assert (apt.cutter.diameter, apt.cutter.corner_radius) == (path.cutter.diameter, path.cutter.corner_radius)
    assert not apt.multax
    back = CLPath.from_apt(apt)
    assert back.feed_length() == pytest.approx(path.feed_length() + 1.0 * len(starts), abs=1e-2)


def test_simulate_run_cuts_the_same_plan_as_the_apt_file(zoned_run, tmp_path):
    out, path, _ = zoned_run
    assert main(["simulate", "--run", str(out), "--grid", "0.5", "--out", str(tmp_path / "run")]) == 0
    by_run = json.loads((tmp_path / "run" / "simulation.json").read_text())
    assert by_run["cl_points"] == len(path) and len(by_run["zones"]) >= 3
    assert main(["simulate", str(out / "config.yaml"), "--apt", str(out / "toolpath.apt"), "--grid", "0.5",
                 "--out", str(tmp_path / "apt")]) == 0
    by_apt = json.loads((tmp_path / "apt" / "simulation.json").read_text())
    # the APT file rounds tips to 1e-4 mm and adds rapids and plunges that cut nothing more
    for key in ("scallop_max_mm", "scallop_p99_mm", "gouge_max_mm", "uncut_fraction"):
        assert by_apt[key] == pytest.approx(by_run[key], abs=3e-4), key


def test_sections_are_left_up_to_the_safe_height_and_entered_from_above():
    tip = np.array([[0, 0, 5], [4, 0, 5], [0, 3, 2], [4, 3, 2.5]], float)
    tp = Toolpath.from_sections("f", Tool(3, make_cutter(6, 1)), tip, np.tile([0.0, 0, 1], (4, 1)), [0, 0, 1, 1], feed=800,
                                clearance=10, gap=1, section_names={1: "ZONE 1 PASS 4"})
    # approach, down, plunge, cut, retract | traverse, down, plunge, cut, retract
    assert np.allclose(tp.tip, [[0, 0, 15], [0, 0, 6], [0, 0, 5], [4, 0, 5], [4, 0, 15],
                                [0, 3, 15], [0, 3, 3], [0, 3, 2], [4, 3, 2.5], [4, 3, 15]])
    assert tp.rapid.tolist() == [True, True, False, False, True] * 2
    assert tp.plunge.tolist() == [False, False, True, False, False] * 2
    assert tp.lengths()["cutting"] == pytest.approx(4 + np.hypot(4, 0.5))
    text = apt_toolpath(tp)
    assert "$$ PASS 0" in text and "$$ ZONE 1 PASS 4" in text and "CUTTER/6.0000,1.0000" in text


def test_zone_borders_are_the_cell_edges_between_zones():
    corners = np.stack([*np.meshgrid(np.arange(4.0), np.arange(3.0), indexing="ij"), np.zeros((4, 3))], -1)
    labels = np.array([[0, 0], [0, 1], [2, 2]])  # (3, 2) cells
    segs = {tuple(map(tuple, s)) for s in border_segments(labels, corners).tolist()}
    assert segs == {((1.0, 1.0), (1.0, 2.0)),  # (0, 1) | (1, 1): zone 0 | 1 across u = 1
                    ((2.0, 0.0), (2.0, 1.0)), ((2.0, 1.0), (2.0, 2.0)),  # row 1 | row 2 across u = 2
                    ((1.0, 1.0), (2.0, 1.0))}  # (1, 0) | (1, 1) across v = 1
