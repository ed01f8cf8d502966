"""The one table of criteria drives every list: weights, objectives, bounds, the simulated
names and the documentation's table."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import yaml
from toolpath_analytic import Plane

from evoplan.cli import main

from evoplan.problems.toolpath.criteria.objective import (
    parse_bounds, parse_objectives, parse_weights, weighted_sum,
)
from evoplan.problems.toolpath.criteria.simulated import SimulatedCriteria
from evoplan.problems.toolpath.criteria.table import CRITERIA, names
from evoplan.problems.toolpath.plan.planner import Planner
from evoplan.problems.toolpath.spec import parse_tools

ROOT = Path(__file__).resolve().parents[3]


def _error(fn, *args) -> str:
    with pytest.raises(ValueError) as info:
        fn(*args)
    return str(info.value)


def test_weights_accept_exactly_the_weightable_criteria_of_the_table():
    accepted = []
    for name in CRITERIA:
        try:
            accepted.append(next(iter(parse_weights({name: 1.0}))))
        except ValueError as err:
            line = str(err)
            assert line.startswith(f"weights.{name}: {name} cannot be weighted"), line
            assert "\n" not in line
    assert tuple(accepted) == names(weightable=True)
    assert {"r_eff", "objective"} == set(CRITERIA) - set(accepted)
    assert {"zones", "link_length", "interzone_length", "eq4_total"} <= set(accepted)


def test_unknown_weights_and_objectives_are_refused_in_one_line():
    line = _error(parse_weights, {"speed": 0.5, "cc_count": 0.5})
    assert line.startswith("weights.speed: unknown criterion 'speed' (known: cc_count, ")
    assert "r_eff" not in line and "\n" not in line
    assert _error(parse_objectives, ["cc_count", "r_eff"]).startswith(
        "objectives[1]: r_eff cannot be weighted")
    assert _error(parse_objectives, "cc_count").startswith("objectives: expected a list")
    assert _error(parse_bounds, {"r_eff": [0, 1]}, ["cc_count"]).startswith(
        "normalization.r_eff: not a weighted criterion")


def test_the_removed_total_length_names_eq4_total():
    """``total_length`` (the removed zoning problem's name of Djebali's Eq. 4 total) is
    refused wherever a criterion is named, with a hint naming ``eq4_total``."""
    assert _error(parse_weights, {"total_length": 0.25, "cc_count": 0.75}) == (
        "weights.total_length: renamed eq4_total")
    assert _error(parse_objectives, ["machining_time", "total_length"]) == (
        "objectives[1]: renamed eq4_total")
    assert _error(parse_bounds, {"total_length": [100, 200]}, ["eq4_total"]) == (
        "normalization.total_length: renamed eq4_total")
    crit = {"eq4_total": np.array([100.0, 150.0, 200.0])}
    w = parse_weights({"eq4_total": 1.0})
    np.testing.assert_allclose(weighted_sum(crit, w, {"eq4_total": (100.0, 200.0)}), [0, 0.5, 1])


def test_a_run_with_an_objective_given_twice_is_refused_in_one_line(tmp_path, capsys):
    """Two identical objectives are one ``evoplan: error`` line naming the entry, exit 2, no
    run folder."""
    path = tmp_path / "dup.yaml"
    path.write_text(yaml.safe_dump({
        "seed": 1, "algorithm": {"name": "nsga2", "pop_size": 8},
        "termination": {"generations": 2},
        "problem": {"name": "toolpath", "params": {
            "objectives": ["eq4_total", "eq4_total"],
            "normalization": {"eq4_total": [0, 1]}}}}))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"evoplan: error: {path}: ") and err.count("\n") == 1, err
    assert err.rstrip().endswith("objectives[1]: eq4_total is given twice"), err
    assert not out.exists()


def test_the_cut_simulation_measures_the_criteria_flagged_simulated():
    tools = parse_tools([{"diameter": 12, "corner_radius": 0}])
    surface = Plane(0.0, 30.0, 0.0, 20.0)
    path = Planner(surface, tools).cl_path({"tool": 0, "stepover": 40.0, "lead": 0.0, "tilt": 3.0,
                                            "step": 10.0})
    measured = SimulatedCriteria(surface, {"grid_mm": 1.0}).measure(path, flat=True)
    # the simulated set, written out: a table edit that changes it must change this line
    assert tuple(measured) == ("scallop_max", "scallop_mean", "gouge_max", "undercut_max",
                               "machining_error", "machining_error_mean")
    assert measured["undercut_max"] == measured["scallop_max"] > 0  # the rim's saw-tooth
    for name in measured:  # each measured criterion can be weighted in a run file
        assert parse_weights({name: 1.0}) == {name: 1.0}


def test_the_documentation_table_lists_every_criterion():
    spec = importlib.util.spec_from_file_location(
        "criteria_table_hook", ROOT / "docs" / "_hooks" / "criteria_table.py")
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    page = (ROOT / "docs/criteria.md").read_text()
    assert hook.MARKER in page
    rendered = hook.on_page_markdown(page, None, None, None)
    rows = [line for line in rendered.splitlines() if line.startswith("| `")]
    assert [row.split("`")[1] for row in rows] == list(CRITERIA)
    for row in rows:
        name = row.split("`")[1]
        assert row.split(" | ")[2] == ("yes" if CRITERIA[name].weightable else "no"), row
    assert "| `eq4_total` | mm | yes |" in rendered and "alias" not in rendered
