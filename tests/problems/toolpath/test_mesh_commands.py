"""Every command on the shipped mesh part (runs/parts/wavy_mesh.stl), small budgets: each output
records the mesh and the measured deviation of the fit the plan was made on."""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import pytest
import yaml

from evoplan.cli import main

pytest.importorskip("trimesh")

ROOT = Path(__file__).resolve().parents[3]
RUN = ROOT / "runs" / "mesh_wavy_zoned_vega.yaml"
MACHINE = ROOT / "runs" / "mesh_wavy_machine.yaml"
PLAN = ["--set", "tool=1", "--set", "stepover=35", "--set", "step=4", "--set", "zones=1"]


def _fit(record: dict) -> dict:
    surface = record["surface"]
    assert surface["type"] == "mesh" and surface["file"] == "wavy_mesh.stl" and surface["triangles"] == 19200
    fit = surface["fit"]
    assert 0 < fit["max_deviation_mm"] <= fit["limit_mm"] == 0.005
    return fit


def test_the_part_is_the_scripts_output(tmp_path):
    out = tmp_path / "p.stl"
    runpy.run_path(str(ROOT / "runs" / "parts" / "make_mesh_part.py"), run_name="not_main")["main"](
        ["--out", str(out)])
    assert out.read_bytes() == (ROOT / "runs" / "parts" / "wavy_mesh.stl").read_bytes()


def test_examples_copy_the_part_with_the_run_file(tmp_path, capsys):
    assert main(["examples"]) == 0
    listed = capsys.readouterr().out
    assert "mesh_wavy_zoned_vega " in listed and "mesh_wavy_machine " in listed
    assert main(["examples", "mesh_wavy_zoned_vega", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "parts" / "wavy_mesh.stl").read_bytes() == (ROOT / "runs/parts/wavy_mesh.stl").read_bytes()
    capsys.readouterr()
    out = tmp_path / "run"
    assert main(["run", str(tmp_path / "mesh_wavy_zoned_vega.yaml"), "--out", str(out), "--quiet",
                 "--set", "algorithm.population=4", "--set", "algorithm.virus.count=1",
                 "--set", "termination.generations=1", "--set", "problem.params.zoning.mesh=[8, 6]",
                 "--set", "problem.params.fixed={zones: 1}",
                 "--set", "problem.params.ranges={stepover: [10, 40], step: [0.5, 4]}"]) == 0
    best = json.loads((out / "best.json").read_text())
    _fit(best)
    assert best["variables"]["tool"] in (1, 2)
    # the results folder records the run file's folder, so its part is found from there
    assert yaml.safe_load((out / "config.yaml").read_text())["problem"]["params"]["base_dir"] == str(tmp_path)
    assert main(["simulate", "--run", str(out), "--grid", "1", "--out", str(tmp_path / "s"), "--quiet"]) == 0
    _fit(json.loads((tmp_path / "s" / "simulation.json").read_text()))


def test_evaluate_and_simulate(tmp_path, capsys):
    assert main(["evaluate", str(RUN), *PLAN, "--out", str(tmp_path / "e")]) == 0
    capsys.readouterr()
    report = json.loads((tmp_path / "e" / "criteria.json").read_text())
    fit = _fit(report)
    assert report["criteria"]["scallop_max"] > 0
    assert main(["simulate", str(RUN), *PLAN, "--grid", "0.5", "--out", str(tmp_path / "s"), "--quiet"]) == 0
    capsys.readouterr()
    sim = json.loads((tmp_path / "s" / "simulation.json").read_text())
    assert _fit(sim) == fit
    # the mesh's simulated cusp against the fit's analytic one: the same within the grid's
    # sampling (0.5 mm cells) and the fit's deviation
    assert sim["scallop_max_mm"] == pytest.approx(report["criteria"]["scallop_max"], abs=0.02)


def test_zone_and_machine(tmp_path, capsys):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "wavy_mesh.stl").write_bytes((ROOT / "runs/parts/wavy_mesh.stl").read_bytes())
    zone = tmp_path / "zone.yaml"
    zone.write_text("name: mesh_zone\nsurface: {type: mesh, file: parts/wavy_mesh.stl}\n"
                    "cutter: {R: 5, r: 5}\nh_c: 0.1\nmesh: [12, 8]\nmethod: kmeans\nkmeans: {K: 2}\n")
    assert main(["zone", str(zone), "--out", str(tmp_path / "z")]) == 0
    _fit(json.loads((tmp_path / "z" / "summary.json").read_text()))
    assert main(["machine", str(MACHINE), "--out", str(tmp_path / "m"), "--quiet"]) == 0
    capsys.readouterr()
    summary = json.loads((tmp_path / "m" / "summary.json").read_text())
    _fit(summary)
    assert 9.0 < summary["surface"]["z_min"] < summary["surface"]["z_max"] < 17.5
    assert summary["finish"]["points"] > 0
