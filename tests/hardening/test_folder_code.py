"""No command runs code that a results folder names: every reader of ``config.yaml`` /
``best.json`` rebuilds the problem from data, and a folder of a user-code run is refused in one
line unless the user names the module with ``--trust-code``."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
KUBOTA = ROOT / "runs" / "kubota_ga.yaml"
PAYLOAD = '''
from pathlib import Path
Path("pwned").write_text("the payload ran")
from pymoo.core.problem import Problem
class P(Problem):
    def __init__(self):
        super().__init__(n_var=1, n_obj=1, xl=0.0, xu=1.0)
    def _evaluate(self, x, out, *args, **kwargs):
        out["F"] = x
'''


@pytest.fixture
def evilrun(tmp_path) -> Path:
    """A results folder that carries its own module and names it as the run's problem."""
    run = tmp_path / "evilrun"
    run.mkdir()
    (run / "payload.py").write_text(PAYLOAD)
    (run / "config.yaml").write_text("seed: 1\nproblem: {name: 'evilrun.payload:P'}\n"
                                     "algorithm: {name: ga, population: 4}\ntermination: {generations: 1}\n")
    (run / "best.json").write_text(json.dumps({"objective": 0.5, "variables": {"x1": 0.5}}))
    return run


def evoplan(cwd: Path, *args):
    """``PYTHONPATH=. python -m evoplan ...`` in ``cwd``: the folder's module is importable."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([".", str(ROOT)]), "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, "-m", "evoplan", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


def refused(result, cwd: Path, *words: str) -> None:
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    for word in words:
        assert word in lines[0], lines[0]
    assert not (cwd / "pwned").exists(), "the folder's module was imported"


def test_simulate_run_refuses_a_folder_naming_user_code(evilrun):
    r = evoplan(evilrun.parent, "simulate", "--run", "evilrun", "--out", "sim")
    refused(r, evilrun.parent, "config.yaml", "problem.name", "--trust-code evilrun.payload")
    assert not (evilrun.parent / "sim").exists()


def test_a_standard_library_module_is_not_imported_either(evilrun):
    (evilrun / "config.yaml").write_text("seed: 1\nproblem: {name: 'this:X'}\n"
                                         "algorithm: {name: ga, population: 4}\ntermination: {generations: 1}\n")
    r = evoplan(evilrun.parent, "simulate", "--run", "evilrun", "--out", "sim")
    refused(r, evilrun.parent, "problem.name", "this:X")
    assert "Beautiful is better than ugly" not in r.stdout + r.stderr  # the Zen of Python: `this` ran


def test_trust_code_is_what_lets_the_module_run(evilrun):
    """The same folder with the module named on the command line: now it is imported (and, not
    being a toolpath problem, refused for that)."""
    r = evoplan(evilrun.parent, "simulate", "--run", "evilrun", "--trust-code", "evilrun.payload",
                "--out", "sim")
    assert (evilrun.parent / "pwned").exists()
    assert r.returncode == 2 and "makes no toolpath" in r.stderr, r.stderr
    assert not (evilrun.parent / "sim").exists()


def test_trusting_another_module_does_not_open_the_door(evilrun):
    r = evoplan(evilrun.parent, "simulate", "--run", "evilrun", "--trust-code", "evilrun", "--out", "sim")
    refused(r, evilrun.parent, "problem.name")


def test_machine_from_run_refuses_it(evilrun):
    r = evoplan(evilrun.parent, "machine", ROOT / "runs" / "abbas_gentle.yaml", "--from-run", "evilrun",
                "--out", "nc")
    refused(r, evilrun.parent, "config.yaml", "problem.name", "--from-run")
    assert not (evilrun.parent / "nc").exists()


def test_resume_builds_from_the_run_file_given_not_the_folder(evilrun):
    r = evoplan(evilrun.parent, "run", KUBOTA, "--resume", "evilrun")
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert not (evilrun.parent / "pwned").exists()
