"""The typed toolpath specification: validated once, one-line errors naming the key path,
the problem built from it, one tool definition from the run file to the NC program."""

import json

import numpy as np
import pytest

from evoplan.cli import main
from evoplan.problems.toolpath import ToolpathProblem, ToolpathSpec
from evoplan.problems.toolpath.cutters import CUTTERS, TaperedBallCutter
from evoplan.problems.toolpath.export import toolpath as export_toolpath
from evoplan.problems.toolpath.geometry.registry import SURFACES
from evoplan.problems.toolpath.plan.zoning.methods import REGISTRY
from evoplan.problems.toolpath.spec import parse_tools, tool_from_text
from evoplan.problems.toolpath.tools import Tool

FIXED = {"tool": 8, "stepover": 30.0, "lead": 2.0, "tilt": 1.0, "step": 8.0}


def _error(**params) -> str:
    with pytest.raises(ValueError) as info:
        ToolpathSpec.from_params(params)
    line = str(info.value)
    assert "\n" not in line and "\x1e" not in line, line
    return line


@pytest.mark.parametrize("params,line", [
    ({"zoning": {"method": "kmean"}}, "zoning.method: expected one of single, kmeans, amas, got 'kmean'"),
    ({"tools": [{"diameter": 6.35, "corner_radius": 9}]}, "tools[0].corner_radius: 9 exceeds the tool radius 3.175"),
    ({"tools": [{"diameter": 8, "corner_radius": 0}, {"diameter": -1}]}, "tools[1].diameter: must be > 0, got -1"),
    ({"tools": [{"id": 1, "diameter": 8, "corner_radius": 0}, {"id": 1, "diameter": 8, "corner_radius": 4}]},
     "tools: duplicate tool id(s) 1"),
    ({"tools": [{"diameter": 8, "corner_radius": 0, "spindle": 9000}]},
     "tools[0].feed: missing (an entry with spindle needs its feed, mm/min)"),
    ({"tools": [{"type": "tapered_ball", "diameter": 8, "corner_radius": 1}]},
     "tools[0].taper_angle: missing (a tapered_ball cutter needs it)"),
    ({"tools": "ball"}, "tools: expected a non-empty list of tools, got 'ball'"),
    ({"dynamics": {"accel": 0}}, "dynamics.accel: must be > 0, got 0"),
    ({"weights": {"total_length": 1.0}}, "weights.total_length: renamed eq4_total"),
    ({"objectives": ["cc_count", "total_length"]}, "objectives[1]: renamed eq4_total"),
    ({"feed_angle": "north"}, "feed_angle: expected a number of degrees or optimized, got 'north'"),
    ({"tolerance": 0}, "tolerance: must be a finite number > 0, got 0"),
    ({"machine": "4axis"}, "machine: expected one of 5axis, 3axis, got '4axis'"),
    ({"placement": "drop"}, "placement: only a 3-axis machine has a placement choice (machine is '5axis')"),
    ({"simulation": {"grid_mm": 1}}, "simulation: only used with criteria: simulated"),
    ({"strategy": ["parallel", "spiral"]},
     "strategy[1]: unknown strategy 'spiral' (known: parallel, isoscallop, contour, isoparametric)"),
    ({"edge_overrun": "yes"}, "edge_overrun: expected true or false, got 'yes'"),
    ({"normalization": {"r_eff": [0, 1]}}, "normalization.r_eff: not a weighted criterion (machining_error, cc_count)"),
])
def test_bad_params_are_one_line_naming_the_key(params, line):
    assert _error(**params) == line


def test_unknown_keys_are_named_with_the_known_ones():
    assert _error(colour=1).startswith("colour: unknown key (known: surface, tools, machine,")
    assert _error(zoning={"method": "kmeans", "colour": 1}) == (
        "zoning.colour: unknown key (known: method, mesh, merge, settings, seed)")
    assert _error(tools=[{"diameter": 8, "colour": 1, "d": 2}]).startswith("tools[0]: unknown keys colour, d (known: id,")
    assert "base_dir" not in _error(colour=1)


# older run files: ``mesh`` directly under the params (now ``zoning: {mesh}``) and a tool's
# ``R`` / ``r`` (now ``diameter`` = 2R, ``corner_radius``) name their new form
@pytest.mark.parametrize("params,line", [
    ({"mesh": [12, 12]}, "mesh: moved under zoning (zoning: {method: METHOD, mesh: [12, 12]})"),
    ({"mesh": [24, 20], "zoning": "kmeans", "machine": "3axis"},
     "mesh: moved under zoning (zoning: {method: kmeans, mesh: [24, 20]})"),
    ({"mesh": [8, 8], "zoning": {"method": "amas"}},
     "mesh: moved under zoning (zoning: {method: amas, mesh: [8, 8]})"),
    ({"tools": [{"id": 1, "type": "ball", "R": 5}]}, "tools[0].R: renamed diameter = 2R (R: 5 is diameter: 10)"),
    ({"tools": [{"diameter": 8, "corner_radius": 0}, {"diameter": 10, "r": 2}]},
     "tools[1].r: renamed corner_radius (r: 2 is corner_radius: 2)"),
    ({"tools": [{"R": 2.5, "r": 1}]}, "tools[0].R: renamed diameter = 2R (R: 2.5 is diameter: 5)"),
])
def test_old_keys_name_their_new_form(params, line):
    assert _error(**params) == line


def test_the_hint_reaches_every_reader_of_a_tool():
    with pytest.raises(ValueError, match=r"^tools\[0\]\.r: renamed corner_radius"):
        parse_tools([{"diameter": 6, "r": 3}])
    with pytest.raises(ValueError, match=r"^--tool '12,R=6': tool\.R: renamed diameter = 2R"):
        tool_from_text("12,R=6")
    assert _error(zoning={"method": "kmeans", "mesh": [12, 12]}, machine="3axis",
                  tools=[{"diameter": 10, "corner_radius": 5, "R": 5}]).startswith("tools[0].R: ")
    ToolpathSpec.from_params({"zoning": {"method": "kmeans", "mesh": [12, 12]}, "machine": "3axis",
                              "tools": [{"diameter": 10, "corner_radius": 2}]})  # the new form


@pytest.mark.parametrize("params,key", [
    ("    mesh: [12, 12]\n    zoning: kmeans\n", "mesh: moved under zoning"),
    ("    tools: [{id: 1, R: 5, r: 5}]\n", "tools[0].R: renamed diameter = 2R"),
])
def test_a_run_file_with_an_old_key_is_one_line_and_writes_nothing(tmp_path, capsys, params, key):
    run = tmp_path / "old.yaml"
    run.write_text("problem:\n  name: toolpath\n  params:\n    machine: 3axis\n" + params
                   + "algorithm: {name: vega, population: 4}\ntermination: {generations: 1}\n")
    out = tmp_path / "res"
    assert main(["run", str(run), "--out", str(out)]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and str(run) in err[0] and key in err[0], err
    assert "Traceback" not in captured.err and not out.exists()


def test_the_problem_is_built_from_the_spec_as_from_keywords():
    params = {"surface": "choi", "tools": [{"id": 8, "type": "ball", "diameter": 6.35}], "tolerance": 0.02,
              "fixed": {"tool": 8}, "normalization_samples": 4}
    spec = ToolpathSpec.from_params(params)
    a, b = ToolpathProblem(spec), ToolpathProblem(**params)
    assert a.spec == b.spec == spec and a.n_var == b.n_var == 4
    X = a.genes.design(3, 1)
    for name, value in a.criteria(X).items():
        np.testing.assert_array_equal(value, b.criteria(X)[name], err_msg=name)
    with pytest.raises(TypeError):
        ToolpathProblem(spec, tolerance=0.05)  # a spec alone, or keywords: not both


def test_the_schema_holds_every_registered_surface_and_cutter():
    schema = ToolpathSpec.json_schema()
    text = json.dumps(schema)
    assert set(schema["properties"]) == set(ToolpathSpec.model_fields) - {"base_dir"}
    for kind in SURFACES:
        assert f'"const": "{kind}"' in text or f'"enum": ["{kind}"]' in text, kind
    assert all(name in text for name in CUTTERS) and all(name in text for name in REGISTRY)


def test_one_tool_definition_from_the_run_file_to_the_nc_program():
    assert export_toolpath.Tool is Tool
    problem = ToolpathProblem(tools=[{"id": 12, "type": "tapered_ball", "diameter": 8,
                                      "corner_radius": 1, "taper_angle": 10, "feed": 800,
                                      "spindle": 12000, "name": "TB8"}],
                              fixed={"tool": 12, "stepover": 30, "lead": 1, "tilt": 0.5, "step": 8})
    tool = problem.tool_db.tools[0]
    assert isinstance(tool.cutter, TaperedBallCutter) and tool.number == 12
    assert (tool.feed, tool.spindle_rpm, tool.label()) == (800.0, 12000.0, "TB8")
    apt = problem.artifacts(np.zeros(0))["toolpath.apt"].decode()
    assert "LOADTL/12" in apt and "SPINDL/12000" in apt
    assert tool.cutter.apt_cutter() in apt  # the tapered ball's 7-parameter CUTTER/


def test_a_command_line_tool_names_any_registered_cutter():
    assert tool_from_text("12,6").cutter.kind == "ball"
    assert tool_from_text("12").cutter.kind == "flat"  # r = 0 without a type
    assert tool_from_text("toroidal:16,3").cutter.corner_radius == 3.0
    cone = tool_from_text("tapered_ball:8,1,taper_angle=10").cutter
    assert isinstance(cone, TaperedBallCutter) and cone.taper_angle == 10.0
    assert tool_from_text("ball:12").cutter.corner_radius == 6.0
    for bad, why in [("0", "tool.diameter: must be > 0"), ("ball:8,1", "tool.type: 'ball' does not match"),
                     ("tapered_ball:8,1", "tool.taper_angle: missing"), ("x", "give [TYPE:]D[,r]"),
                     ("cone:8,1", "tool.type: expected one of")]:
        with pytest.raises(ValueError, match=r"^--tool '" + bad + "': ") as info:
            tool_from_text(bad)
        assert why in str(info.value)


def test_simulate_cuts_an_nc_program_with_a_tapered_ball(tmp_path, capsys):
    """``--tool tapered_ball:8,1,taper_angle=10`` cuts an outside program with the same
    cutter the plan was made with: the same residual as simulating the plan itself."""
    import yaml

    from evoplan.problems.toolpath.export.kinematics import Kinematics, Rotary
    from evoplan.problems.toolpath.export.posts import POSTS, Machine
    from evoplan.problems.toolpath.export.toolpath import Toolpath

    tool = {"id": 3, "type": "tapered_ball", "diameter": 8, "corner_radius": 1, "taper_angle": 10}
    run = tmp_path / "tapered.yaml"
    run.write_text(yaml.safe_dump({"problem": {"name": "toolpath", "params": {"tools": [tool]}},
                                   "algorithm": {"name": "ga", "population": 4},
                                   "termination": {"generations": 1}}))
    params = dict(stepover=35.0, lead=1.0, tilt=0.5, step=10.0)
    problem = ToolpathProblem(tools=[tool])
    path, _ = problem.cl_path(params)
    tp = Toolpath.from_sections("finish", problem.tool_db.tools[0], path.tip, path.axis,
                                path.section, feed=1000)
    kin = Kinematics("table_table", Rotary("A", "x", (-120, 120)), Rotary("C", "z", (-1e6, 1e6)))
    (tmp_path / "f.nc").write_text(POSTS["fanuc"](Machine(kin, safe_z=60.0)).program(tp))
    sets = [a for k, v in params.items() for a in ("--set", f"{k}={v}")]
    common = ["--grid", "1.0", "--quiet"]
    assert main(["simulate", str(run), *sets, *common, "--out", str(tmp_path / "a")]) == 0
    assert main(["simulate", str(run), "--nc", str(tmp_path / "f.nc"), "--tool",
                 "tapered_ball:8,1,taper_angle=10", *common, "--out", str(tmp_path / "b")]) == 0
    a, b = (json.loads((tmp_path / x / "simulation.json").read_text()) for x in "ab")
    for key in ("scallop_max_mm", "scallop_mean_mm", "gouge_max_mm", "uncut_fraction"):
        assert b[key] == pytest.approx(a[key], abs=3e-4), key
    capsys.readouterr()
    assert main(["simulate", str(run), "--nc", str(tmp_path / "f.nc"), "--tool",
                 "tapered_ball:8,1", "--out", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--tool 'tapered_ball:8,1': tool.taper_angle: missing" in err[0]
    assert not (tmp_path / "c").exists()


SIM = {"criteria": "simulated"}


@pytest.mark.parametrize("simulation,line", [
    ({"rays": "x"}, "simulation.rays: expected normal or vertical, got 'x'"),
    ({"grid_mm": 0}, "simulation.grid_mm: must be a positive number of mm"),
    ({"grid_mm": "fine"}, "simulation.grid_mm: must be a positive number of mm"),
    ({"allowance": -1}, "simulation.allowance: must be a positive number of mm"),
    ({"threads": 1.5}, "simulation.threads: expected a whole number of threads >= 1, got 1.5"),
    ({"colour": 1}, "simulation.colour: unknown setting (known: allowance, grid_mm, rays, screening, threads)"),
    (5, "simulation: expected a mapping of settings, got 5"),
    ({"screening": 0.25}, "simulation.screening: expected a mapping (fraction, correction, neighbours, error_quantile), got 0.25"),
    ({"screening": {"share": 1}}, "simulation.screening.share: unknown setting (known: correction, error_quantile, fraction, neighbours)"),
    ({"screening": {"neighbours": True}}, "simulation.screening.neighbours: expected a whole number >= 1, got True"),
])
def test_bad_simulation_settings_are_one_line_naming_the_key(simulation, line):
    assert _error(**SIM, simulation=simulation) == line


def test_the_simulation_settings_are_typed_in_the_spec_and_the_criteria_take_them():
    from evoplan.problems.toolpath.criteria.screening import ScreeningSettings
    from evoplan.problems.toolpath.criteria.simulated import SimulatedCriteria, SimulationSettings

    spec = ToolpathSpec.from_params({**SIM, "simulation": {"grid_mm": 2, "rays": "vertical",
                                                           "screening": {"fraction": 0.5}}})
    assert isinstance(spec.simulation, SimulationSettings) and spec.simulation.grid_mm == 2.0
    assert spec.simulation.screening == ScreeningSettings(fraction=0.5)
    problem = ToolpathProblem(spec)
    sim = problem.simulated
    assert sim.settings is spec.simulation and sim.vertical and sim.grid_mm == 2.0
    assert sim.screening.fraction == 0.5 and sim.screening.correction == "ratio"
    assert ToolpathProblem(**SIM, fixed=FIXED).simulated.settings == SimulationSettings()
    # a plain mapping given to the criteria directly is validated by the same model
    assert SimulatedCriteria(None, {"grid_mm": 2, "rays": "vertical",
                                    "screening": {"fraction": 0.5}}).settings == spec.simulation
    with pytest.raises(ValueError, match=r"^simulation\.rays: expected normal or vertical"):
        SimulatedCriteria(None, {"rays": "sideways"})


@pytest.mark.parametrize("params,line", [
    ({"ranges": {"stepover": [0, 40]}}, "ranges.stepover: must be > 0, got 0"),
    ({"ranges": {"stepover": [20, 120]}}, "ranges.stepover: a step-over above 100 % of D leaves material uncut, got 120"),
    ({"ranges": {"lead": [5, 0]}}, "ranges.lead: expected finite lo < hi, got [5, 0]"),
    ({"ranges": {"tilt": [0, 95]}}, "ranges.tilt: angles must lie in (-90, 90) degrees, got 95"),
    ({"ranges": {"step": "long"}}, "ranges.step: expected [lo, hi], got 'long'"),
    ({"ranges": {"lead": 0}}, "ranges.lead: expected [lo, hi], got 0 (to fix a gene, write fixed: {lead: 0})"),
    ({"ranges": {"zones": 3}}, "ranges.zones: expected [lo, hi], got 3 (to fix a gene, write fixed: {zones: 3})"),
    ({"ranges": {"tool": [1, 2]}}, "ranges.tool: the tool is a choice over the tool database (list fewer "
                                   "tools, or fix one with fixed: {tool: ID})"),
    ({"ranges": {"lead": [0, 1]}, "fixed": {"lead": 0}},
     "ranges.lead: lead is fixed (fixed.lead); give a range or a fixed value, not both"),
    ({"ranges": [1, 2]}, "ranges: expected a mapping gene -> [lo, hi], got [1, 2]"),
    ({"fixed": {"tilt": 95}}, "fixed.tilt: angles must lie in (-90, 90) degrees, got 95"),
    ({"fixed": {"step": 0}}, "fixed.step: must be > 0, got 0"),
    ({"fixed": {"stepover": "wide"}}, "fixed.stepover: expected a number, got 'wide'"),
])
def test_gene_values_are_checked_by_the_spec(params, line):
    """A gene's value is checked without building the planner: one line naming the key."""
    assert _error(**params) == line


def test_the_spec_types_the_gene_values_and_leaves_the_configurations_genes_to_the_problem():
    spec = ToolpathSpec.from_params({"ranges": {"stepover": [25, 30], "lead": [1, 1], "zones": [2, 5]},
                                     "fixed": {"tool": 8, "step": 6}})
    assert spec.ranges.stepover == (25.0, 30.0) and spec.fixed.step == 6.0
    assert spec.ranges.given() == {"stepover": (25.0, 30.0), "lead": (1.0, 1.0), "zones": [2, 5]}
    assert spec.fixed.given() == {"tool": 8, "step": 6.0}  # the tool id: checked against the database
    # the configuration's genes: no zoning here, so no zones gene (the problem says so)
    with pytest.raises(ValueError, match=r"^ranges.zones: not a gene of this configuration"):
        ToolpathProblem(spec)
    problem = ToolpathProblem(ranges={"stepover": [25, 30], "lead": [1, 1]}, fixed={"tool": 8, "step": 6},
                              normalization_samples=2)
    assert problem.fixed == {"tool": 8, "lead": 1.0, "step": 6.0}  # the one-point range is fixed
    assert problem.ranges == {"stepover": (25.0, 30.0), "tilt": (0.0, 2.0)}
