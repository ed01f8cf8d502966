"""The APT file and every post's NC program name the part's surface in their header: its
type and file and, for a mesh (a height field fitted to the triangles), the fit's largest
measured deviation, as best.json / criteria.json / simulation.json record it."""

import json
from pathlib import Path

import numpy as np
import pytest

from evoplan.cli import main
from evoplan.problems.toolpath.cutters import make_cutter
from evoplan.problems.toolpath.export.apt_read import read_apt
from evoplan.problems.toolpath.export.kinematics import Kinematics, Rotary
from evoplan.problems.toolpath.export.posts import POSTS, Machine
from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath, surface_comment
from evoplan.problems.toolpath.geometry.spec import parse_surface

ROOT = Path(__file__).resolve().parents[3]
RUN = ROOT / "runs" / "mesh_wavy_zoned_vega.yaml"
STL = ROOT / "runs" / "parts" / "wavy_mesh.stl"
PLAN = ["--set", "tool=1", "--set", "stepover=35", "--set", "step=4", "--set", "zones=1"]


def _deviation_line(text: str) -> str:
    lines = [ln for ln in text.splitlines() if "surface: mesh wavy_mesh.stl" in ln.lower()]
    assert len(lines) == 1, text[:600]
    return lines[0]


def test_the_apt_and_the_nc_header_carry_the_fit_deviation(tmp_path, capsys):
    pytest.importorskip("trimesh")
    run = tmp_path / "mesh.yaml"
    run.write_text(RUN.read_text().replace("parts/wavy_mesh.stl", str(STL))
                   .replace("mesh: [24, 16]", "mesh: [8, 6]")
                   .replace("    machine: 3axis\n", "    machine: 3axis\n    feed_rate: 1200\n"))
    out = tmp_path / "ev"
    assert main(["evaluate", str(run), *PLAN, "--out", str(out), "--post", "iso"]) == 0
    capsys.readouterr()
    dev = json.loads((out / "criteria.json").read_text())["surface"]["fit"]["max_deviation_mm"]
    assert 0 < dev <= 0.005
    want = f"surface: mesh wavy_mesh.stl, fit max deviation {dev:.4g} mm"
    apt = (out / "toolpath.apt").read_text()
    assert _deviation_line(apt) == f"$$ {want}"
    assert apt.index(want) < apt.index("$$ TOOLPOINT")  # in the header, before any motion
    assert read_apt(out / "toolpath.apt").tip.shape[0] > 100  # and the file still reads
    nc = (out / "program.nc").read_text()
    assert _deviation_line(nc) == f"({want.upper()})"
    assert nc.index(want.upper()) < nc.index("G21")


@pytest.mark.parametrize("name", sorted(POSTS))
def test_every_post_writes_the_surface_line_in_its_header(name):
    pytest.importorskip("trimesh")
    surface = parse_surface({"type": "mesh", "file": str(STL)})
    line = surface_comment(surface, {"type": "mesh", "file": "parts/wavy_mesh.stl"})
    dev = surface.facts()["fit"]["max_deviation_mm"]
    assert line == f"surface: mesh wavy_mesh.stl, fit max deviation {dev:.4g} mm"
    m = 30
    x = np.linspace(0, 40, m)
    tip = np.column_stack([x, np.zeros(m), np.sin(x / 9)])
    tp = Toolpath.from_passes("finish", Tool(3, make_cutter(10, 5), 9000), tip, np.tile([0.0, 0, 1], (m, 1)),
                              np.arange(m) * 2 // m, feed=1200, comments=["a title", line])
    kin = Kinematics("table_table", Rotary("A", "x", (-30, 110)), Rotary("C", "z", (-360, 360)))
    post = POSTS[name](Machine(kin if POSTS[name].five_axis else None))
    text = post.program(tp)
    header = text.split("T3")[0]  # before the tool call: the header's comments
    assert line.upper() in header.upper() and max(map(len, text.splitlines())) <= 72
    read = post.read(text).tip  # it parses back: every cutting point is a point of the program
    read = read[np.isfinite(read).all(axis=1)]
    assert np.abs(tip[:, None, :] - read[None]).max(axis=2).min(axis=1).max() < 1e-3


def test_an_exact_surface_names_its_type_alone():
    assert surface_comment(parse_surface("fountas"), "fountas") == "surface: fountas"
    assert surface_comment(parse_surface("choi")) == f"surface: {type(parse_surface('choi')).__name__}"
