"""A lighter install: single-feature libraries are extras, named in one line when missing."""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

import pytest

from evoplan.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_test_extra_pulls_in_every_feature_extra():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    extras = project["optional-dependencies"]
    pulled = set()
    for req in extras["test"]:
        m = re.fullmatch(r"evoplan\[([a-z,\s]+)\]", req)
        if m:
            pulled |= {e.strip() for e in m.group(1).split(",")}
    features = set(extras) - {"test", "profile"}
    assert features and features <= pulled
    base = " ".join(project["dependencies"])
    for lib in ("deap", "dask", "ioh", "mkdocs", "ezdxf", "numpy-stl"):
        assert lib not in base  # not in the base install


@pytest.mark.parametrize("module, algorithm, extra", [("deap", "deap_easimple", "deap")])
def test_missing_adapter_library_is_one_line(tmp_path, capsys, monkeypatch, module, algorithm, extra):
    monkeypatch.setitem(sys.modules, module, None)  # import deap -> ImportError
    path = tmp_path / "r.yaml"
    path.write_text(f"problem: {{name: kubota}}\nalgorithm: {{name: {algorithm}}}\ntermination: {{generations: 2}}\n")
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f'pip install "evoplan[{extra}]"' in err
    assert not (tmp_path / "out").exists()


def test_missing_ioh_names_the_bbob_extra(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ioh", None)
    study = tmp_path / "s.yaml"
    study.write_text("seeds: 1\nbudget: {evaluations: 20}\nproblems: [{name: bbob-f3, dimensions: [2]}]\n"
                     "algorithms: [{name: ga, population: 10}]\n")
    assert main(["study", str(study), "--out", str(tmp_path / "s"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and 'pip install "evoplan[bbob]"' in err


@pytest.mark.parametrize("module", ["ezdxf", "stl"])
def test_missing_exchange_library_is_one_line(tmp_path, capsys, monkeypatch, module):
    monkeypatch.setitem(sys.modules, module, None)
    out = tmp_path / "m"
    assert main(["machine", str(ROOT / "runs" / "abbas_gentle.yaml"), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and 'pip install "evoplan[exchange]"' in err
    assert not out.exists()
