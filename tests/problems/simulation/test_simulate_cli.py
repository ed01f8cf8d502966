"""``evoplan simulate``: a parameter set, an APT file, a finished run; bad input."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from evoplan.cli import main
from evoplan.problems.toolpath.problem import ToolpathProblem

ROOT = Path(__file__).resolve().parents[3]
RUN = ROOT / "runs" / "fountas_toolpath_vega.yaml"
PARAMS = dict(tool=8, stepover=30.0, lead=1.0, tilt=0.5, step=8.0)
SETS = [a for k, v in PARAMS.items() for a in ("--set", f"{k}={v}")]
KEYS = ("scallop_max_mm", "scallop_mean_mm", "scallop_p99_mm", "gouge_max_mm", "gouge_area_mm2",
        "uncut_fraction", "grid_mm", "cl_points", "seconds")


def _simulate(tmp_path, name, *args, capsys=None):
    out = tmp_path / name
    code = main(["simulate", *map(str, args), "--grid", "0.5", "--out", str(out)])
    return code, out


@pytest.fixture(scope="module")
def by_set(tmp_path_factory):
    out = tmp_path_factory.mktemp("sim") / "set"
    assert main(["simulate", str(RUN), *SETS, "--grid", "0.5", "--out", str(out)]) == 0
    return out, json.loads((out / "simulation.json").read_text())


def test_a_parameter_set_writes_the_record_and_figures(by_set):
    out, rec = by_set
    for key in KEYS:
        assert key in rec
    assert sorted(p.name for p in out.iterdir()) == ["deviation.npz", "deviation_hist.png", "deviation_map.png",
                                                     "simulation.json", "toolpath.apt"]
    with np.load(out / "deviation.npz", allow_pickle=False) as d:   # the report's data: the map itself
        assert d["residual"].shape == d["z"].shape == d["inside"].shape and float(d["h"]) == 0.5
    assert rec["grid_mm"] == 0.5 and rec["cl_points"] > 100
    assert 0 < rec["scallop_mean_mm"] <= rec["scallop_p99_mm"] <= rec["scallop_max_mm"]


def test_apt_written_then_simulated_gives_the_same_numbers(by_set, tmp_path):
    pr = ToolpathProblem()
    apt = pr.artifacts(pr.row(PARAMS)[0])["toolpath.apt"]
    # statements that do not move the tool are read, counted and listed, not refused
    (tmp_path / "plan.apt").write_bytes(b"PAINT/COLOR,36\nINDIRV/1,0,0\nPPRINT KEEP\nPAINT/PATH\n" + apt)
    code, out = _simulate(tmp_path, "apt", RUN, "--apt", tmp_path / "plan.apt")
    assert code == 0
    rec = json.loads((out / "simulation.json").read_text())
    assert rec["ignored_statements"] == {"INDIRV": 1, "PAINT": 2, "PPRINT": 1}
    assert "ignored_statements" not in by_set[1]  # a plan from --set reads no file
    ref = by_set[1]
    # the APT file rounds tips to 1e-4 mm and adds an approach and a retract in the air
    for key in ("scallop_max_mm", "scallop_mean_mm", "scallop_p99_mm", "gouge_max_mm", "uncut_fraction"):
        assert rec[key] == pytest.approx(ref[key], abs=3e-4), key


def test_the_best_plan_of_a_finished_run(by_set, tmp_path):
    run = tmp_path / "run"
    run.mkdir()
    shutil.copy(RUN, run / "config.yaml")
    (run / "best.json").write_text(json.dumps({"objective": 0.1, "variables": PARAMS}))
    code, out = _simulate(tmp_path, "fromrun", "--run", run)
    assert code == 0
    rec = json.loads((out / "simulation.json").read_text())
    assert rec["scallop_p99_mm"] == pytest.approx(by_set[1]["scallop_p99_mm"], abs=1e-12)


BAD_APT = {
    "garbage": "CUTTER/12,6\nMULTAX/ON\nGOTO/1,2,3,0,0,1\nthis is not apt\nGOTO/2,2,3,0,0,1\n",
    "no_cutter": "MULTAX/ON\nGOTO/-50,-50,30,0,0,1\nGOTO/-40,-50,30,0,0,1\n",
    "nan": "CUTTER/12,6\nGOTO/-50,-50,nan\nGOTO/-40,-50,30\n",
    "empty": "PARTNO/EMPTY\nCUTTER/12,6\nFINI\n",
    "off_part": "CUTTER/12,6\nGOTO/500,500,30\nGOTO/510,500,30\nFINI\n",
}


@pytest.mark.parametrize("case", sorted(BAD_APT))
def test_bad_apt_files_get_one_line(case, tmp_path, capsys):
    f = tmp_path / f"{case}.apt"
    f.write_text(BAD_APT[case])
    code, out = _simulate(tmp_path, "out", RUN, "--apt", f)
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists()
    assert err.startswith("evoplan: error:") and "\n" not in err and str(f) in err


def test_a_grid_too_fine_for_memory_is_refused_with_the_estimate(tmp_path, capsys):
    out = tmp_path / "fine"
    code = main(["simulate", str(RUN), *SETS, "--grid", "0.0005", "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists()
    assert "GiB" in err and "grid_mm" in err and "\n" not in err


@pytest.mark.parametrize("grid, words", [("1e-300", "more memory than exists"), ("1e6", "too coarse")])
def test_absurd_grids_name_the_grid(grid, words, tmp_path, capsys):
    out = tmp_path / "absurd"
    code = main(["simulate", str(RUN), *SETS, "--grid", grid, "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists()
    assert "grid_mm" in err and words in err and "\n" not in err


@pytest.mark.parametrize("args", [["--grid", "-1"], ["--set", "tool=99"], []])
def test_bad_arguments_get_one_line(args, tmp_path, capsys):
    out = tmp_path / "x"
    base = [a for a in SETS] if args and args[0] == "--grid" else []
    code = main(["simulate", str(RUN), *base, *args, "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and not out.exists() and "\n" not in err


def test_simulated_criteria_are_the_cut_simulation_of_the_plan():
    from evoplan.problems.toolpath.simulation import design_grid, simulate

    norm = {"machining_error": [0, 0.5], "cc_count": [0, 1000]}
    pr = ToolpathProblem(criteria="simulated", simulation={"grid_mm": 1.0}, normalization=norm)
    x = pr.row(PARAMS)
    crit = pr.criteria(x)
    sim = simulate(pr.cl_path(PARAMS)[0], design_grid(pr.surface, 1.0))
    assert crit["scallop_max"][0] == pytest.approx(sim.metrics["scallop_max_mm"])
    assert crit["gouge_max"][0] == pytest.approx(sim.metrics["gouge_max_mm"])
    assert crit["machining_error"][0] == max(crit["scallop_max"][0], crit["gouge_max"][0])
    F = pr.evaluate(x)
    assert np.isfinite(F).all()
    with pytest.raises(ValueError, match="simulation.rays"):
        ToolpathProblem(criteria="simulated", simulation={"rays": "sideways"}, normalization=norm)
    with pytest.raises(ValueError, match="criteria"):
        ToolpathProblem(criteria="dreamed", normalization=norm)


def _on_a_terminal(argv, cwd):
    """Run ``python -m evoplan ARGV`` with a pseudo-terminal as stdout and stderr; its output."""
    import os
    import pty
    import subprocess
    import sys

    import fcntl
    import struct
    import termios

    leader, follower = pty.openpty()
    fcntl.ioctl(follower, termios.TIOCSWINSZ, struct.pack("HHHH", 30, 120, 0, 0))  # a terminal's size
    env = {**os.environ, "MPLBACKEND": "Agg", "COLUMNS": "120"}
    proc = subprocess.Popen([sys.executable, "-m", "evoplan", *argv], stdout=follower, stderr=follower,
                            cwd=cwd, env=env)
    os.close(follower)
    chunks = []
    while True:
        try:
            data = os.read(leader, 4096)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    assert proc.wait(timeout=300) == 0
    os.close(leader)
    return b"".join(chunks).decode(errors="replace")


def test_progress_on_a_terminal_and_quiet_silences_it(tmp_path):
    base = ["simulate", str(RUN), *SETS, "--grid", "0.5"]
    shown = _on_a_terminal([*base, "--out", "a"], tmp_path)
    assert "simulate: 4/4" in shown and "sweep of" in shown
    quiet = _on_a_terminal([*base, "--out", "b", "--quiet"], tmp_path)
    assert "simulate:" not in quiet and "scallop_max_mm" in quiet
