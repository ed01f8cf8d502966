"""A key given twice with ``--set`` is refused in one line, whatever the command."""

from __future__ import annotations

from pathlib import Path

import pytest

from evoplan.cli import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("argv", [
    ["run", ROOT / "runs" / "kubota_ga.yaml", "--set", "algorithm.population=30",
     "--set", "algorithm.population=40"],
    ["run", ROOT / "runs" / "kubota_ga.yaml", "--set", "seed=1", "--set", " seed =2"],
    ["study", ROOT / "runs" / "kubota_vega_vs_ga.yaml", "--set", "seeds=2", "--set", "seeds=3"],
    ["evaluate", ROOT / "runs" / "fountas_toolpath_vega.yaml", "--set", "tool=6", "--set", "stepover=41.7",
     "--set", "lead=3", "--set", "tilt=0", "--set", "step=6", "--set", "tool=7"],
])
def test_a_key_set_twice_is_refused(argv, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main([str(a) for a in argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "given twice" in err[0], err
    assert not (tmp_path / "results").exists()


def test_different_keys_still_apply_in_order(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["run", str(ROOT / "runs" / "kubota_ga.yaml"), "--set", "algorithm.population=6",
                 "--set", "termination.generations=2", "--out", str(out), "--quiet"]) == 0
    assert "population: 6" in (out / "config.yaml").read_text()
