"""Loud failures: a missing extra stops a study before it starts; failed cells give exit code 3
and their variants are left out of the tests, ranks and figures, which the report says."""

from __future__ import annotations

import re
import sys

import pandas as pd
import pytest

from evoplan.cli import main
from evoplan.errors import ConfigError
from evoplan.study import runner
from evoplan.study.config import parse_study

STUDY = {"seed": 1, "seeds": 3, "budget": {"evaluations": 40}, "problems": [{"name": "kubota"}],
         "algorithms": [{"name": "ga", "population": 6}, {"name": "vega", "population": 6},
                        {"name": "ga", "label": "ga8", "population": 8}, {"name": "ga", "label": "ga10", "population": 10}],
         "output": {"plots": True, "ioh": False}}


def test_a_study_needing_a_missing_extra_is_refused_naming_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "deap", None)  # import deap raises ImportError
    data = {**STUDY, "algorithms": [{"name": "ga"}, {"name": "deap_easimple"}]}
    with pytest.raises(ConfigError, match=r"algorithms\[1\] \(deap_easimple\).*evoplan\[deap\]"):
        parse_study(data, "s.yaml")


def test_failed_cells_exit_3_and_their_variant_is_left_out(tmp_path, monkeypatch, capsys):
    real = runner.run_cell

    def vega_fails(cell):
        record, history, trace = real(cell)
        if cell.algorithm == "vega":
            record.update(status="failed", error="RuntimeError: injected")
        return record, history, trace

    monkeypatch.setattr(runner, "run_cell", vega_fails)
    import evoplan.figure_style as style

    figures, png = [], style.png
    monkeypatch.setattr(style, "png", lambda fig: figures.append(fig) or png(fig))
    import yaml
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(STUDY))
    out = tmp_path / "out"
    assert main(["study", str(path), "--out", str(out), "--quiet"]) == 3
    err = capsys.readouterr().err
    assert "3 of 12 runs failed" in err
    ranks = pd.read_csv(out / "friedman.csv")
    assert ranks["variants"].tolist() == [3]  # ga, ga8, ga10: not vega
    pairs = pd.read_csv(out / "nemenyi.csv").to_string()
    assert "vega" not in pairs and "ga8" in pairs
    assert "vega" not in pd.read_csv(out / "tests.csv").to_string()
    report = (out / "report.md").read_text()
    assert "left out of the tests, ranks and figures" in report and "vega (3 of 3 runs failed)" in report
    assert len(pd.read_csv(out / "runs.csv")) == 12  # every run is still a row
    # the CD diagram draws ga, ga8 and ga10, and its caption names vega as left out
    (cd,) = [f for f in figures if any("mean rank" in ax.get_title() for ax in f.axes)]
    drawn = {re.sub(r"\([^)]*\)", "", t.get_text()).strip() for t in cd.axes[0].texts}  # "ga8 (2)", "(3) ga"
    assert drawn == {"ga", "ga8", "ga10"}, drawn
    assert [t.get_text() for t in cd.texts] == ["left out (failed runs): vega (3 of 3 runs failed)"]
