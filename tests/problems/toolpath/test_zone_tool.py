"""``evoplan zone``'s cutter is a run file's tools entry (``tool:``): any registered cutter,
a tapered ball-end too; the older ``cutter: {R, r}`` reads as the same tool."""

from __future__ import annotations

import json

import pytest

from evoplan.cli import main
from evoplan.problems.toolpath.cutters import make_cutter

BASE = "surface: choi\nmesh: [16, 16]\nmethod: kmeans\nkmeans: {K: 2}\n"
TAPERED = ("tool: {id: 4, type: tapered_ball, diameter: 8, corner_radius: 1, taper_angle: 10, "
           "feed: 800, spindle: 12000}\n")


def _zone(tmp_path, name, text, h_c=0.254):
    (tmp_path / f"{name}.yaml").write_text(BASE + f"h_c: {h_c}\n" + text)
    code = main(["zone", str(tmp_path / f"{name}.yaml"), "--out", str(tmp_path / name), "--quiet"])
    return code, tmp_path / name


def test_a_zone_file_names_a_tapered_ball_as_a_tools_entry(tmp_path, capsys):
    code, out = _zone(tmp_path, "tb", TAPERED)
    assert code == 0
    facts = json.loads((out / "summary.json").read_text())
    assert facts["cutter"] == {"type": "tapered_ball", "diameter": 8.0, "corner_radius": 1.0,
                               "taper_angle": 10.0}
    apt = (out / "toolpath.apt").read_text()
    cone = make_cutter(8.0, 1.0, "tapered_ball", taper_angle=10.0)
    assert "LOADTL/4" in apt and cone.apt_cutter() in apt and "SPINDL/12000" in apt
    assert "FEDRAT/800.0000" in apt  # the tool's own feed
    # under the height where the cone meets the ball, r (1 - sin 10 deg) = 0.83 mm, a cusp of
    # h_c = 0.254 mm lies on the tip ball: the plan of a ball of radius r; above it the cone
    # widens the cut, so the passes spread and the path is shorter than the ball's
    code, ball = _zone(tmp_path, "ball", "tool: {type: ball, diameter: 2}\n")
    assert code == 0
    assert json.loads((ball / "summary.json").read_text())["total_length_mm"] == facts["total_length_mm"]
    code_c, cone_high = _zone(tmp_path, "cone_high", TAPERED, h_c=1.5)
    code_b, ball_high = _zone(tmp_path, "ball_high", "tool: {type: ball, diameter: 2}\n", h_c=1.5)
    assert code_c == code_b == 0
    lengths = [json.loads((d / "summary.json").read_text())["total_length_mm"] for d in (cone_high, ball_high)]
    assert lengths[0] < 0.95 * lengths[1], lengths


def test_the_older_cutter_form_is_the_same_tool(tmp_path, capsys):
    code_a, a = _zone(tmp_path, "a", "cutter: {R: 3.175, r: 1.0}\n")
    code_b, b = _zone(tmp_path, "b", "tool: {diameter: 6.35, corner_radius: 1.0}\n")
    code_c, c = _zone(tmp_path, "c", "")  # the default: Djebali's toroidal cutter
    assert code_a == code_b == code_c == 0
    facts = [json.loads((d / "summary.json").read_text()) for d in (a, b, c)]
    for f in facts:
        f.pop("seconds"), f.pop("name")
    assert facts[0] == facts[1] == facts[2]
    assert facts[0]["cutter"] == {"type": "toroidal", "diameter": 6.35, "corner_radius": 1.0}
    apts = [[line for line in (d / "toolpath.apt").read_text().splitlines() if not line.startswith("$$")]
            for d in (a, b, c)]
    assert apts[0] == apts[1] == apts[2]


@pytest.mark.parametrize("text,line", [
    ("tool: {type: tapered_ball, diameter: 8, corner_radius: 1}\n",
     "tool.taper_angle: missing (a tapered_ball cutter needs it)"),
    ("tool: {diameter: -1, corner_radius: 0}\n", "tool.diameter: must be > 0, got -1"),
    ("tool: {diameter: 8, corner_radius: 1, colour: red}\n", "tool.colour: unknown key (known: id, type,"),
    ("cutter: {type: ball, diameter: 8}\n", "cutter.diameter: cutter holds only R and r; write any "
     "registered cutter as a run file's tools entry: tool: {type, diameter, corner_radius, ...}"),
    ("tool: {diameter: 8, corner_radius: 1}\ncutter: {R: 4, r: 1}\n", "cutter: give the cutter once"),
    ("cutter: {R: 3, r: 4}\n", "cutter.r: the corner radius must be in [0, R = 3.0], got 4.0"),
])
def test_a_bad_tool_is_one_line_naming_the_key_and_writes_nothing(tmp_path, capsys, text, line):
    code, out = _zone(tmp_path, "bad", text)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and not out.exists()
    assert f"bad.yaml: {line}" in err[0], err[0]
