"""``evoplan evaluate ... --out DIR [--post NAME]``: the plan's criteria, APT, zone map and NC program;
``evoplan simulate ... --out DIR``: the plan's APT beside the measures."""

import json
from pathlib import Path

import numpy as np

from evoplan.cli import main
from evoplan.problems.toolpath.export.apt_read import read_apt
from evoplan.problems.toolpath.export.kinematics import Kinematics, Rotary
from evoplan.problems.toolpath.export.posts import POSTS, Machine
from evoplan.problems.toolpath.export.safety import check_program

RUN = Path(__file__).resolve().parents[3] / "runs" / "fountas_toolpath_vega.yaml"
SETS = ["--set", "tool=8", "--set", "stepover=30", "--set", "lead=1", "--set", "tilt=0.5", "--set", "step=8"]


def test_a_plan_exported_with_its_nc_program(tmp_path, capsys):
    out = tmp_path / "ev"
    assert main(["evaluate", str(RUN), *SETS, "--out", str(out), "--post", "fanuc"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert {p.name for p in out.iterdir()} == {"criteria.json", "toolpath.apt", "toolpath.npz", "zone_map.png", "cc_pattern.png",
                                               "program.nc"}
    assert json.loads((out / "criteria.json").read_text()) == printed
    apt = read_apt(out / "toolpath.apt")
    kin = Kinematics("table_table", Rotary("A", "x", (-30, 110)), Rotary("C", "z", (-360, 360)))
    post = POSTS["fanuc"](Machine(kin))
    text = (out / "program.nc").read_text()
    moves = post.read(text)
    tips = moves.tip[np.isfinite(moves.tip).all(axis=1)]
    # every APT cutting point is a point of the program
    cut = apt.tip[~apt.rapid]
    d = np.abs(tips[None, :, :] - cut[:: max(1, len(cut) // 50), None, :]).max(axis=2).min(axis=1)
    assert d.max() < 2e-3
    assert check_program(post, text, tips[:, 2].max() - 1e-6).ok


def test_a_three_axis_post_for_a_five_axis_plan_writes_nothing(tmp_path, capsys):
    out = tmp_path / "ev"
    assert main(["evaluate", str(RUN), *SETS, "--out", str(out), "--post", "iso"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "3-axis post" in err[0] and "problem.params.machine" in err[0] and not out.exists()
    # decided from the run file: a 3-axis plan passes it (and is refused next, for its missing feed)
    run = tmp_path / "three.yaml"
    run.write_text(RUN.read_text().replace("    feed_rate: 1000\n", "    machine: 3axis\n"))
    assert main(["evaluate", str(run), "--set", "tool=8", "--out", str(out), "--post", "iso"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "feed_rate: missing" in err[0] and not out.exists(), err
    assert main(["evaluate", str(RUN), *SETS, "--out", str(out), "--post", "okuma"]) == 2
    assert "unknown post" in capsys.readouterr().err and not out.exists()


def test_the_apt_plunges_at_the_tools_plunge_feed_as_the_nc_program_does(tmp_path, capsys):
    # no feed_rate: the tool's own feed is the plan's
    text = RUN.read_text().replace(
        "    feed_rate: 1000\n", "    tools: [{diameter: 12, corner_radius: 6, feed: 800, plunge_feed: 123}]\n")
    run = tmp_path / "run.yaml"
    run.write_text(text)
    out = tmp_path / "ev"
    assert main(["evaluate", str(run), *SETS[2:], "--out", str(out), "--post", "fanuc"]) == 0
    apt = read_apt(out / "toolpath.apt")
    cut = ~apt.rapid
    plunge = cut & np.r_[False, apt.rapid[:-1]]  # the first feed move after a rapid
    assert plunge.sum() > 1 and np.all(apt.feed[plunge] == 123) and np.all(apt.feed[cut & ~plunge] == 800)
    nc = (out / "program.nc").read_text()
    assert nc.count("F123.") == plunge.sum() and "FEDRAT/123.0000,MMPM" in (out / "toolpath.apt").read_text()


def test_an_nc_program_needs_the_feed_of_its_tool_from_the_run_file(tmp_path, capsys):
    cases = {  # tools (None: the default nine, which have no feed) -> the key named
        None: "problem.params.feed_rate: missing",
        "[{diameter: 12, corner_radius: 6}]": "problem.params.tools[0].feed: missing",
        "[{id: 4, diameter: 12, feed: 900}, {id: 7, diameter: 12, corner_radius: 6}]": "problem.params.tools[1].feed",
    }
    for n, (tools, words) in enumerate(cases.items()):
        text = RUN.read_text().replace("    feed_rate: 1000\n", f"    tools: {tools}\n" if tools else "")
        run = tmp_path / f"run{n}.yaml"
        run.write_text(text)
        out = tmp_path / f"ev{n}"
        tool = ["--set", "tool=7"] if n == 2 else []
        assert main(["evaluate", str(run), *SETS[2:], *tool, "--out", str(out), "--post", "fanuc"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f"{run}: {words}" in err[0] and "--post" in err[0] and not out.exists(), err
    # a geometry-only entry is fine where no NC program is written
    assert main(["evaluate", str(tmp_path / "run1.yaml"), *SETS[2:]]) == 0
    assert "objective" in json.loads(capsys.readouterr().out)


def test_simulate_writes_the_plan_it_cut_as_toolpath_apt(tmp_path, capsys):
    from evoplan.problems.toolpath.problem import ToolpathProblem

    out = tmp_path / "sim"
    assert main(["simulate", str(RUN), *SETS, "--grid", "0.5", "--quiet", "--out", str(out)]) == 0
    rec = json.loads((out / "simulation.json").read_text())
    text = (out / "toolpath.apt").read_text()
    # the moves of evaluate --out's toolpath.apt (the comments name the command)
    pr = ToolpathProblem()
    params = dict(tool=8, stepover=30, lead=1, tilt=0.5, step=8)
    ref = pr.artifacts(pr.row(params)[0])["toolpath.apt"].decode()
    moves = [ln for ln in text.splitlines() if not ln.startswith(("$$", "PARTNO"))]
    assert moves == [ln for ln in ref.splitlines() if not ln.startswith(("$$", "PARTNO"))]
    apt = read_apt(out / "toolpath.apt")
    path, _ = pr.cl_path(params)
    assert rec["cl_points"] == len(path) and apt.cutter.diameter == 12 and apt.cutter.corner_radius == 6
    np.testing.assert_allclose(apt.tip[~apt.rapid], path.tip, atol=5e-5)  # every CL point cut, in order
