"""The toolpath problem through the ``evoplan`` command: evaluate, run with artifacts, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.test_cli import evoplan, write

ROOT = Path(__file__).resolve().parents[3]
VEGA_SET = ["--set", "tool=6", "--set", "stepover=41.729", "--set", "lead=2.957", "--set", "tilt=0.027",
            "--set", "step=6.338"]


def test_evaluate_prints_every_criterion_of_the_published_vega_set():
    proc = evoplan("evaluate", ROOT / "runs" / "fountas_toolpath_vega.yaml", *VEGA_SET)
    assert proc.returncode == 0, proc.stderr
    report = json.loads(proc.stdout)
    c = report["criteria"]
    assert c["cc_count"] == 289 and c["n_passes"] == 17  # 17 planes x 17 points, as in the paper
    for key in ("chord_error_mean", "chord_error_max", "scallop_max", "machining_error", "path_length",
                "machining_time"):
        assert c[key] > 0
    assert c["chord_error_max"] <= 0.01 + 1e-9  # the cut tolerance holds
    assert c["machining_time_nominal"] == pytest.approx(c["path_length"] / 1000.0)
    assert report["objective"] == pytest.approx(c["objective"])


TOOLPATH_RUN = """
seed: 2
problem:
  name: toolpath
  params: {params}
{extra}algorithm: {{name: vega, population: 8, virus: {{count: 2}}}}
termination: {{generations: 2}}
"""


def test_run_writes_cc_pattern_and_apt_file(tmp_path):
    cfg = write(tmp_path / "t.yaml", TOOLPATH_RUN.format(params="{surface: fountas}", extra=""))
    proc = evoplan("run", cfg, "--out", tmp_path / "res")
    assert proc.returncode == 0, proc.stderr
    out = tmp_path / "res"
    for name in ("cc_pattern.png", "zone_map.png"):  # a single zone has its zone map too
        assert (out / name).read_bytes()[:4] == b"\x89PNG", name
    apt = (out / "toolpath.apt").read_text().splitlines()
    assert apt[0].startswith("PARTNO/") and apt[-1] == "FINI" and "MULTAX/ON" in apt
    assert max(len(line) for line in apt) <= 72
    gotos = [line for line in apt if line.startswith("GOTO/")]
    best = json.loads((out / "best.json").read_text())
    assert set(best["variables"]) == {"tool", "stepover", "lead", "tilt", "step"}
    assert best["variables"]["tool"] in range(1, 10)
    assert len(gotos) >= 2 and all(len(g.split("/")[1].split(",")) == 6 for g in gotos)
    # one section per pass of the single zone, each opened by its comment
    sections = [line for line in apt if line.startswith("$$ ZONE ")]
    assert sections[:2] == ["$$ ZONE 0 PASS 0", "$$ ZONE 0 PASS 1"] and len(sections) >= 10


NURBS = ("{{surface: {{type: nurbs, degree: [2, 1], weights: {w}, poles: [[[0, 0, 0], [0, 1, 0]], "
         "[[1, 0, 1], [1, 1, 1]], [[2, 0, 0], [2, 1, 0]]]}}}}")
BAD_PARAMS = {
    "net_shape": ("{surface: {type: bezier, poles: [[[0, 0, 0], [1, 0, 0]], [[0, 1, 0]]]}}", "surface"),
    "net_nan": ("{surface: {type: bezier, poles: [[[0, 0, .nan], [1, 0, 0]], [[0, 1, 0], [1, 1, 0]]]}}", "surface"),
    "nurbs_weights_nan": (NURBS.format(w="[[1, 1], [.nan, 1], [1, 1]]"),
                          "surface.weights: contains NaN or infinite values"),
    "nurbs_weights_shape": (NURBS.format(w="[[1, 1], [1, 1]]"),
                            "surface.weights: expected shape (3, 2) (one weight per pole)"),
    "corner_radius": ("{tools: [{id: 1, type: toroidal, diameter: 8, corner_radius: 5}]}", "corner"),
    "weights_sum": ("{weights: {machining_error: 0.7, cc_count: 0.5}}", "weights"),
    "machine": ("{machine: 4axis}", "machine: expected one of 5axis, 3axis"),
    "lead_3axis": ("{machine: 3axis, ranges: {lead: [0, 2]}}", "ranges.lead: not a gene of this "
                   "configuration (machine 3axis has no lead/tilt)"),
    "zones_single": ("{ranges: {zones: [1, 4]}}", "ranges.zones: not a gene"),
    "fixed_range": ("{fixed: {tilt: 120}}", "fixed.tilt: angles must lie in (-90, 90)"),
    "fixed_bits": ("{fixed: {lead: 1}}\n  variables: {lead: {bits: 8}}",
                   "variables.lead: fixed at 1 by the problem's params (fixed.lead): not a "
                   "variable, so it has no bits"),
}


@pytest.mark.parametrize("case", sorted(BAD_PARAMS))
def test_bad_toolpath_input_is_one_line_exit_2(tmp_path, case):
    params, key = BAD_PARAMS[case]
    params, _, extra = params.partition("\n")
    cfg = write(tmp_path / f"{case}.yaml", TOOLPATH_RUN.format(params=params, extra=extra and extra + "\n"))
    proc = evoplan("run", cfg, "--out", tmp_path / "res")
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr
    assert key in lines[0] and str(cfg) in lines[0]
    assert not (tmp_path / "res").exists()
