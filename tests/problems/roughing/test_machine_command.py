"""``evoplan machine``: every file written and readable; bad input is one line, exit 2, no files."""

import io
import json
import subprocess
import time
import sys

import ezdxf
import numpy as np
import pytest
from stl import mesh as stl_mesh

from evoplan.cli import main as cli_main
from evoplan.problems.toolpath.export.apt_read import read_apt
from evoplan.problems.toolpath.export.kinematics import Kinematics, Rotary
from evoplan.problems.toolpath.export.posts import POSTS, Machine

SMALL = """name: small
surface:
  type: bezier
  poles:
    - [[0, 0, 0], [0, 15, 4], [0, 30, 0]]
    - [[20, 0, 4], [20, 15, 14], [20, 30, 4]]
    - [[40, 0, 0], [40, 15, 4], [40, 30, 0]]
stock: {{cell: 1.0{top}}}
roughing: {{method: {method}, max_depth: {depth}, tool: {{diameter: 8}}}}
semifinish: {{stepover: 4, step: 3}}
finish: {{params: {{tool: 8, stepover: 40, lead: 2, tilt: 0, step: 8}}}}
post: {{dialect: {dialect}, kinematics: {{tilt: {{name: B, about: y, limits: {limits}}}, layout: head_table{kin}}}}}
"""


def machine(tmp_path, *args):
    return subprocess.run([sys.executable, "-m", "evoplan", "machine", *map(str, args)], capture_output=True,
                          text=True, cwd=tmp_path, timeout=300)


def config(tmp_path, method="zlevel", depth=3.0, dialect="heidenhain", limits="[-90, 90]", top="", kin=""):
    path = tmp_path / "m.yaml"
    path.write_text(SMALL.format(method=method, depth=depth, dialect=dialect, limits=limits, top=top, kin=kin))
    return path


def test_machine_writes_every_file(tmp_path):
    proc = machine(tmp_path, config(tmp_path), "--out", tmp_path / "out", "--check")
    assert proc.returncode == 0, proc.stderr
    printed = json.loads(proc.stdout.strip().splitlines()[-1])  # --check says what held
    assert set(printed["check"]) == {"roughing", "semifinish", "finish"} and printed["check"]["finish"]["ok"]
    assert printed["finish"]["nc_file"] == "finish.h"
    out = tmp_path / "out"
    names = {p.name for p in out.iterdir()}
    # a Heidenhain TNC program is a .h file (it was .nc whatever the dialect)
    assert names == {"roughing.h", "semifinish.h", "finish.h", "roughing.apt", "semifinish.apt", "finish.apt",
                     "surface.dxf", "surface.stl", "toolpaths.dxf", "layers.png", "summary.json"}
    summary = json.loads((out / "summary.json").read_text())
    rough = summary["roughing"]
    assert rough["method"] == "zlevel" and rough["n_layers"] == int(np.ceil(rough["d_layers"] / 3.0 - 1e-9))
    assert 0 < rough["max_depth"] <= 3.0 and rough["rapid_volume"] == 0
    assert rough["left_min"] >= summary["roughing"]["allowance"] - 0.011
    for op in ("roughing", "semifinish", "finish"):
        assert summary[op]["nc_file"] == f"{op}.h"
        assert summary[op]["nc_bytes"] == (out / f"{op}.h").stat().st_size > 0
    assert summary["finish"]["multi_axis"] and not summary["roughing"]["multi_axis"]
    assert summary["finish"]["safety"]["violations"] == [] and summary["finish"]["safety"]["clearance_plane"] == \
        pytest.approx(summary["stock"]["z_top"] + 20)
    # the NC programs parse with the dialect's grammar and the APT files read back
    kin = Kinematics("head_table", Rotary("B", "y", (-90, 90)), Rotary("C", "z", (-360, 360)))
    post = POSTS["heidenhain"](Machine(kin))
    for op in ("roughing", "semifinish", "finish"):
        moves = post.read((out / f"{op}.h").read_text())
        tp = read_apt(out / f"{op}.apt")
        # the APT's last point is among the last moves (then the rise to the clearance plane)
        assert np.abs(moves.tip[-4:] - tp.tip[-1]).max(axis=1).min() < 1e-3
        assert tp.multax == (op == "finish") and tp.cutter.diameter > 0
    doc = ezdxf.read(io.StringIO((out / "surface.dxf").read_text()))
    grid = doc.modelspace().query("POLYLINE")[0]
    assert grid.is_polygon_mesh and len(list(grid.vertices)) == grid.dxf.m_count * grid.dxf.n_count
    paths = ezdxf.read(io.StringIO((out / "toolpaths.dxf").read_text()))
    layers = {e.dxf.layer for e in paths.modelspace()}
    assert {"ROUGHING", "SEMIFINISH", "FINISH", "ROUGHING_RAPID"} <= layers
    declared = {layer.dxf.name for layer in paths.layers}
    assert layers <= declared  # every layer used is in the LAYER table
    assert "SURFACE" in {layer.dxf.name for layer in doc.layers}
    assert paths.layers.get("FINISH_RAPID").dxf.linetype == "DASHED" and "DASHED" in paths.linetypes
    auditor = paths.audit()
    assert not auditor.has_errors, [str(e) for e in auditor.errors]
    surf = stl_mesh.Mesh.from_file(str(out / "surface.stl"))
    assert abs(surf.vectors[..., 2].max() - summary["surface"]["z_max"]) < 1e-2 and np.all(surf.normals[:, 2] > 0)


BAD = {
    "depth_zero": (dict(depth=0), "roughing.max_depth"),
    "depth_above_stock": (dict(depth=50), "roughing.max_depth"),
    "unknown_dialect": (dict(dialect="okuma"), "post.dialect: unknown post 'okuma'"),
    "unreachable": (dict(limits="[-3, 3]"), "post.kinematics: finish: point"),
    "stock_below": (dict(top=", top: 5"), "stock.top"),
    "iso_5axis_finish": (dict(dialect="iso"), "post.dialect: iso is a 3-axis post and the finish is 5-axis"),
    "clearance_below_stock": (dict(kin=", clearance_plane: 3"), "post.kinematics.clearance_plane: 3 is below the stock"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_is_one_line_exit_2_no_files(tmp_path, case, capsys):
    kw, words = BAD[case]
    t0 = time.perf_counter()
    code = cli_main(["machine", str(config(tmp_path, **kw)), "--out", str(tmp_path / "out")])
    assert code == 2
    if case == "iso_5axis_finish":  # refused before any operation is planned (was after ~23 s)
        assert time.perf_counter() - t0 < 5.0
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("evoplan: error: ") and words in lines[0], lines
    assert not (tmp_path / "out").exists()


RUN_CONFIG = """seed: 1
problem:
  name: toolpath
  params:
    surface:
      type: bezier
      poles:
        - [[0, 0, 0], [0, 15, 4], [0, 30, {z}]]
        - [[20, 0, 4], [20, 15, 14], [20, 30, 4]]
        - [[40, 0, 0], [40, 15, 4], [40, 30, 0]]
    feed_rate: 1500
"""


def test_finish_from_a_finished_run(tmp_path, capsys):
    run = tmp_path / "run"
    run.mkdir()
    (run / "best.json").write_text(json.dumps(
        {"objective": 0.1, "variables": {"tool": 9, "stepover": 35.0, "lead": 1.0, "tilt": 0.5, "step": 7.0}}))
    (run / "config.yaml").write_text(RUN_CONFIG.format(z=0))
    code = cli_main(["machine", str(config(tmp_path, dialect="fanuc")), "--out", str(tmp_path / "out"),
                     "--from-run", str(run)])
    assert code == 0
    finish = json.loads((tmp_path / "out" / "summary.json").read_text())["finish"]
    assert finish["from_run"] and finish["params"] == {"tool": 9, "stepover": 35.0, "lead": 1.0, "tilt": 0.5,
                                                        "step": 7.0}
    apt = read_apt(tmp_path / "out" / "finish.apt")
    assert apt.cutter.diameter == 16 and np.nanmax(apt.feed) == 1500          # the run's tool and feed rate
    (run / "config.yaml").write_text(RUN_CONFIG.format(z=9))         # another surface
    code = cli_main(["machine", str(config(tmp_path, dialect="fanuc")), "--out", str(tmp_path / "out2"),
                     "--from-run", str(run)])
    assert code == 2 and "another surface" in capsys.readouterr().err and not (tmp_path / "out2").exists()


ZONED_RUN = RUN_CONFIG.format(z=0) + """    machine: 3axis
    zoning: {method: kmeans, mesh: [12, 12], merge: false}
"""


def test_finish_from_a_zoned_3axis_run_is_the_runs_own_plan(tmp_path):
    """The finish comes from the run's whole problem: a zoned 3-axis run gives its vertical,
    zone-by-zone plan (the same CL points as the problem's ``cl_path``), cut in sections."""
    from evoplan.problems.toolpath import ToolpathProblem

    run = tmp_path / "run"
    run.mkdir()
    variables = {"tool": 9, "stepover": 35.0, "step": 7.0, "zones": 2}
    (run / "best.json").write_text(json.dumps({"objective": 0.1, "variables": variables}))
    (run / "config.yaml").write_text(ZONED_RUN)
    code = cli_main(["machine", str(config(tmp_path, dialect="fanuc")), "--out", str(tmp_path / "out"),
                     "--from-run", str(run)])
    assert code == 0
    finish = json.loads((tmp_path / "out" / "summary.json").read_text())["finish"]
    assert finish["params"] == variables and not finish["multi_axis"]
    import yaml

    params = yaml.safe_load(ZONED_RUN)["problem"]["params"]
    path, _ = ToolpathProblem(**params, normalization_samples=2).cl_path(variables)
    assert len(np.unique(path.zone)) == 2
    apt = read_apt(tmp_path / "out" / "finish.apt")
    cut = ~apt.rapid
    np.testing.assert_allclose(apt.tip[cut], path.tip, atol=1e-3)  # the plan's CL points, in order
    assert apt.rapid.sum() >= 3 * len(np.unique(path.section))  # every section entered and left by rapids


def test_progress_names_every_stage_and_quiet_silences_it(tmp_path):
    from evoplan.commands.machine import load
    from evoplan.problems.toolpath.roughing.operation_set import build_operations

    seen = []
    build_operations(load(str(config(tmp_path))).model_dump(), tmp_path, progress=seen.append)
    assert seen == ["roughing", "semi-finish", "finish", "post roughing", "post semifinish", "post finish", "files"]
    proc = machine(tmp_path, config(tmp_path), "--out", tmp_path / "q", "--quiet")
    assert proc.returncode == 0 and proc.stderr == ""


def test_post_tolerance_reduces_the_three_axis_programs_only(tmp_path):
    from evoplan.commands.machine import load
    from evoplan.problems.toolpath.roughing.operation_set import build_operations

    cfg = load(str(config(tmp_path, method="morphing", dialect="fanuc"))).model_dump()
    plain, s0 = build_operations(cfg, tmp_path)
    cfg["post"]["tolerance"] = 0.01
    reduced, s1 = build_operations(cfg, tmp_path)
    assert len(reduced["roughing.nc"]) < len(plain["roughing.nc"])
    assert reduced["finish.nc"] == plain["finish.nc"]  # 5-axis: the rotaries move, every point is kept
    assert s1["finish"]["safety"]["violations"] == [] and s1["roughing"]["safety"]["violations"] == []
    # every point of the roughing program read back lies on the unreduced one within the tolerance
    kin = Kinematics("head_table", Rotary("B", "y", (-90, 90)), Rotary("C", "z", (-360, 360)))
    post = POSTS["fanuc"](Machine(kin))
    a, b = (post.read(p["roughing.nc"].decode()).tip for p in (plain, reduced))
    from evoplan.problems.toolpath.export.arcs import segment_distance

    a, b = a[np.isfinite(a).all(axis=1)], b[np.isfinite(b).all(axis=1)]
    d = np.min([segment_distance(a, b[k], b[k + 1]) for k in range(len(b) - 1)], axis=0)
    assert d.max() <= 0.01 + 1e-4


def test_check_refuses_a_program_that_breaks_a_rule(tmp_path, capsys, monkeypatch):
    from evoplan.problems.toolpath.export.safety import SafetyReport
    from evoplan.problems.toolpath.roughing import operation_set

    real = operation_set.check_program

    def broken(post, text, safe_z):  # the finish as if its retract before G49 were missing
        rep = real(post, text, safe_z)
        if "(FINISH)" in text[:300]:
            rep = SafetyReport(["move 812: TCP is cancelled at Z 7.000, below the clearance plane 45.000"])
        return rep

    monkeypatch.setattr(operation_set, "check_program", broken)
    cfg = str(config(tmp_path, dialect="fanuc"))
    assert cli_main(["machine", cfg, "--out", str(tmp_path / "out"), "--check", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--check: finish.nc breaks 1 safety rule(s), first: move 812: TCP is cancelled" in err[0]
    assert not (tmp_path / "out").exists()
    # without --check the program is written and its summary names the broken rule
    assert cli_main(["machine", cfg, "--out", str(tmp_path / "w"), "--quiet"]) == 0
    assert json.loads((tmp_path / "w" / "summary.json").read_text())["finish"]["safety"]["violations"]
