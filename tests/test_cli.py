"""The ``evoplan`` command, run as a user runs it (a subprocess), on good and bad files."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from evoplan.cli import main
from evoplan.commands import COMMANDS

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}


def evoplan(*args, cwd=None, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "evoplan", *map(str, args)], capture_output=True,
                          text=True, env=ENV, cwd=cwd, timeout=120, **kw)


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


GOOD = """
seed: 3
problem: {name: kubota, bits: 23}
algorithm: {name: vega, population: 20, virus: {count: 7, max_length: 40, infectivity_force: 0.001, infection_rate: 0.7}}
termination: {generations: 10}
"""


def test_run_writes_every_result_file(tmp_path):
    cfg = write(tmp_path / "k.yaml", GOOD)
    out = tmp_path / "res"
    proc = evoplan("run", cfg, "--out", out)
    assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in out.iterdir()) == [
        "best.json", "checkpoint.npz", "config.yaml", "convergence.png", "history.csv"]
    best = json.loads((out / "best.json").read_text())
    assert set(best["variables"]) == {"x", "y"} and best["seed"] == 3
    assert best["algorithm"] == "vega" and best["problem"] == "kubota" and best["failures"] == 0
    history = pd.read_csv(out / "history.csv")
    assert list(history.columns) == ["generation", "evaluations", "best", "mean", "worst", "std", "failures", "cache_hits", "seconds"]
    assert len(history) == 11 and history["evaluations"].iloc[-1] == best["evaluations"]
    assert history["cache_hits"].iloc[-1] == best["cache_hits"] > 0
    assert best["objective"] == pytest.approx(history["best"].iloc[-1])
    assert (out / "convergence.png").read_bytes()[:4] == b"\x89PNG"
    resolved = (out / "config.yaml").read_text()
    assert "min_infection_rate" in resolved and "every_seconds" in resolved  # defaults recorded
    assert json.loads(proc.stdout.strip().splitlines()[-1])["evaluations"] == best["evaluations"]


def test_seed_option_overrides_the_file(tmp_path):
    cfg = write(tmp_path / "k.yaml", GOOD)
    assert main(["run", str(cfg), "--out", str(tmp_path / "a"), "--seed", "11", "--quiet"]) == 0
    assert json.loads((tmp_path / "a" / "best.json").read_text())["seed"] == 11


BAD = {
    "unknown_key": ("problem: {name: kubota, bitz: 3}\nalgorithm: {name: ga}\ntermination: {generations: 2}\n",
                    "problem.bitz"),
    "wrong_type": ("problem: {name: kubota}\nalgorithm: {name: ga, population: many}\ntermination: {generations: 2}\n",
                   "algorithm.population"),
    "bad_bounds": ("problem: {name: kubota, variables: {x: {low: 1, high: -1}}}\nalgorithm: {name: ga}\n"
                   "termination: {generations: 2}\n", "problem.variables.x"),
    "unknown_algorithm": ("problem: {name: kubota}\nalgorithm: {name: pso}\ntermination: {generations: 2}\n",
                          "algorithm.name"),
    "unknown_problem": ("problem: {name: kubotta}\nalgorithm: {name: ga}\ntermination: {generations: 2}\n",
                        "kubotta"),
    "unknown_variable": ("problem: {name: kubota, variables: {z: {bits: 3}}}\nalgorithm: {name: ga}\n"
                         "termination: {generations: 2}\n", "variables.z"),
    "bad_yaml": ("problem: {name: kubota\nalgorithm: [\n", "invalid YAML"),
    "no_termination": ("problem: {name: kubota}\nalgorithm: {name: ga}\ntermination: {}\n", "termination"),
    "bad_virus_rate": ("problem: {name: kubota}\nalgorithm: {name: vega, virus: {max_infection_rate: 0.3}}\n"
                       "termination: {generations: 2}\n", "algorithm.virus.max_infection_rate"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_file_gives_one_line_exit_2_and_no_folder(tmp_path, case):
    text, key = BAD[case]
    cfg = write(tmp_path / f"{case}.yaml", text)
    out = tmp_path / "res"
    proc = evoplan("run", cfg, "--out", out)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert key in lines[0] and str(cfg) in lines[0]
    assert not out.exists()


def test_missing_file(tmp_path):
    proc = evoplan("run", tmp_path / "nope.yaml", "--out", tmp_path / "res")
    assert proc.returncode == 2 and "nope.yaml: no such file" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and not (tmp_path / "res").exists()


def test_existing_results_are_never_overwritten(tmp_path):
    cfg = write(tmp_path / "k.yaml", GOOD)
    (tmp_path / "res").mkdir()
    (tmp_path / "res" / "keep.txt").write_text("mine")
    proc = evoplan("run", cfg, "--out", tmp_path / "res")
    assert proc.returncode == 2 and "not empty" in proc.stderr
    assert (tmp_path / "res" / "keep.txt").read_text() == "mine"


def test_failing_black_box_is_counted_in_best_json(tmp_path):
    cfg = write(tmp_path / "f.yaml", "problem: {name: 'tests.blackboxes:Flaky'}\n"
                "algorithm: {name: ga, population: 12}\ntermination: {generations: 10}\nseed: 7\n")
    proc = evoplan("run", cfg, "--out", tmp_path / "res")
    assert proc.returncode == 0, proc.stderr
    best = json.loads((tmp_path / "res" / "best.json").read_text())
    assert best["failures"] > 0 and best["objective"] is not None
    assert any("solver diverged" in m for m in best["failure_messages"])


SLOW = """
seed: 5
problem: {{name: 'tests.blackboxes:Slow', params: {{delay: {delay}}}}}
algorithm: {{name: vega, population: 10, virus: {{count: 3}}}}
termination: {{generations: 30}}
checkpoint: {{every_generations: 1}}
"""


def comparable(out: Path):
    history = pd.read_csv(out / "history.csv").drop(columns="seconds")
    best = json.loads((out / "best.json").read_text())
    best.pop("wall_seconds")
    return history, best


def test_resume_after_sigkill_gives_the_uninterrupted_result(tmp_path):
    slow = write(tmp_path / "slow.yaml", SLOW.format(delay=0.02))
    killed = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "evoplan", "run", str(slow), "--out", str(killed)],
                            env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 60
    while time.time() < deadline and proc.poll() is None:
        ckpt = killed / "checkpoint.npz"
        if ckpt.exists() and ckpt.stat().st_size > 0:
            time.sleep(0.3)  # a few generations in
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run ended before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not (killed / "best.json").exists()

    resumed = evoplan("run", slow, "--resume", killed)
    assert resumed.returncode == 0, resumed.stderr
    fresh = evoplan("run", slow, "--out", tmp_path / "fresh")
    assert fresh.returncode == 0, fresh.stderr
    h1, b1 = comparable(killed)
    h2, b2 = comparable(tmp_path / "fresh")
    pd.testing.assert_frame_equal(h1, h2)
    assert b1 == b2


def test_resume_refuses_another_configuration(tmp_path):
    cfg = write(tmp_path / "k.yaml", GOOD)
    assert evoplan("run", cfg, "--out", tmp_path / "res").returncode == 0
    other = write(tmp_path / "o.yaml", GOOD.replace("population: 20", "population: 22"))
    proc = evoplan("run", other, "--resume", tmp_path / "res")
    assert proc.returncode == 2 and "algorithm" in proc.stderr
    proc = evoplan("run", cfg, "--resume", tmp_path / "nothing")
    assert proc.returncode == 2 and "no checkpoint.npz" in proc.stderr


def test_evaluate_prints_one_parameter_set(tmp_path):
    cfg = write(tmp_path / "k.yaml", GOOD)
    proc = evoplan("evaluate", cfg, "--set", "x=0", "--set", "y=0")
    assert proc.returncode == 0, proc.stderr
    report = json.loads(proc.stdout)
    assert report["variables"] == {"x": 0, "y": 0} and report["objective"] == pytest.approx(0.0, abs=1e-15)
    for args, message in [(("--set", "x=3", "--set", "y=0"), "outside its range"),
                          (("--set", "x=0"), "missing --set for: y"),
                          (("--set", "x=0", "--set", "y=0", "--set", "q=1"), "no such variable"),
                          (("--set", "x=zero", "--set", "y=0"), "expected a number")]:
        proc = evoplan("evaluate", cfg, *args)
        assert proc.returncode == 2 and message in proc.stderr
        assert len(proc.stderr.strip().splitlines()) == 1


HEAVY = ("numba", "scipy.interpolate", "sklearn", "evoplan.problems.toolpath", "matplotlib", "pandas", "numpy")


@pytest.mark.parametrize("words", [[], ["run"], ["study"], ["evaluate"], ["simulate"], ["examples"],
                                   ["zone"], ["machine"], ["report"]])
def test_help_loads_no_heavy_module(words):
    """``evoplan [COMMAND] --help`` builds only the parser it shows: the toolpath engine, numba and
    scipy are not imported (the parser of every other command is a placeholder)."""
    code = ("import sys\nfrom evoplan.cli import build_parser\n"
            f"parser = build_parser({words!r})\n"
            "print(' '.join(m for m in " + repr(HEAVY) + " if m in sys.modules))\n"
            "print(' '.join(parser._subparsers._group_actions[0].choices))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    loaded, commands = r.stdout.splitlines()
    assert loaded == ""
    assert commands.split() == list(COMMANDS)


def test_zone_and_machine_help_build_no_pydantic_model():
    code = "import sys\nfrom evoplan.cli import build_parser\nbuild_parser(['zone']); build_parser(['machine'])\n" \
           "print('pydantic' in sys.modules)"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and r.stdout.strip() == "False", r.stderr


def test_the_names_zone_help_lists_are_the_registered_ones():
    from evoplan.commands.zone import STRATEGY_NAMES, ZONING_METHODS
    from evoplan.problems.toolpath.plan.strategies import STRATEGIES
    from evoplan.problems.toolpath.plan.zoning.methods import REGISTRY

    assert ZONING_METHODS == tuple(REGISTRY) and STRATEGY_NAMES == tuple(STRATEGIES)


def test_the_backends_study_help_lists_are_the_pools():
    from evoplan.commands.study import BACKENDS
    from evoplan.parallel import POOLS

    assert BACKENDS == tuple(POOLS)


def test_every_command_is_listed_and_runs_with_its_own_options(capsys):
    assert main(["examples"]) == 0  # a command's options come from its module when it is chosen
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    for name, text in COMMANDS.items():
        assert name in out and text.split()[0] in out
