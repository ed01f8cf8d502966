"""``evoplan report``: one self-contained HTML page of a results folder, read as data only."""

from __future__ import annotations

import base64
import json
import re

import numpy as np
import pytest

from evoplan.cli import main

plotly = pytest.importorskip("plotly")


def figures(html: str) -> list[dict]:
    """The plotly figures' data arrays embedded in the page (Plotly.newPlot calls)."""
    out = []
    for m in re.finditer(r'Plotly\.newPlot\(\s*"[^"]+",\s*(\[.*?\]),\s*\{', html, re.S):
        out.append(json.loads(m.group(1)))
    return out


def values(array) -> list:
    """A trace's array as a list (plotly 6 writes numpy arrays as base64 typed arrays)."""
    if isinstance(array, dict):
        array = np.frombuffer(base64.b64decode(array["bdata"]), dtype=array["dtype"]).tolist()
    return [None if isinstance(v, float) and np.isnan(v) else v for v in array]


def test_run_report_is_one_offline_page(kubota_run, tmp_path, capsys):
    out = tmp_path / "r.html"
    assert main(["report", str(kubota_run), "--out", str(out)]) == 0
    html = out.read_text()
    assert html.count("Plotly.newPlot") == 1  # convergence only: no toolpath in a kubota run
    assert not re.search(r"<script[^>]+src=", html)  # plotly.js inlined, nothing fetched
    assert len(html) > 1_000_000  # the bundle itself is inside
    (traces,) = figures(html)
    names = [t["name"] for t in traces]
    assert "best so far" in names and "population mean" in names
    best = next(t for t in traces if t["name"] == "best so far")
    ys = values(best["y"])
    assert len(ys) == 9 and all(a >= b for a, b in zip(ys, ys[1:]))
    band = next(t for t in traces if t["name"].startswith("population band"))
    assert band["fill"] == "tonexty"
    # the best decisions from best.json, and the objective
    best_json = json.loads((kubota_run / "best.json").read_text())
    assert f"{best_json['objective']:.6g}" in html and "<td>x</td>" in html


def test_toolpath_run_draws_passes_rapids_dashed_equal_axes(toolpath_run, capsys):
    assert main(["report", str(toolpath_run)]) == 0
    html = (toolpath_run / "report.html").read_text()
    assert html.count("Plotly.newPlot") == 2
    assert '"aspectmode":"data"' in html
    assert "8 points, 1 rapid move, tool D10 mm" in html
    assert "decimated within 0.005 mm of the programmed path" in html  # the one decimation, stated
    traces = {t["name"]: t for t in figures(html)[1]}
    assert {"zone 0", "rapids"} <= set(traces) and "cuts" not in traces  # no stray group of start points
    rapids = traces["rapids"]
    assert rapids["line"]["dash"] == "dash"
    # the rapid out of pass 0: from its last point (20, 0, 2) up to (20, 5, 20)
    assert [values(rapids[k])[:3] for k in "xyz"] == [[20, 20, None], [0, 5, None], [2, 20, None]]
    cut = traces["zone 0"]
    assert values(cut["x"]).count(None) == 1  # passes 0 and 1, broken at the rapid between them
    assert values(cut["line"]["color"])[-1] == 1  # shaded by pass


def test_toolpath_npz_adds_the_part_the_cc_points_and_the_criteria(toolpath_run):
    from evoplan.report.run import plan_data

    u, v = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 4), indexing="ij")
    mesh = np.stack([20 * u, 5 * v, 0.1 * u], axis=-1)
    np.savez_compressed(toolpath_run / "toolpath.npz", cc=mesh.reshape(-1, 3), zone=np.zeros(20, int),
                        pass_index=np.zeros(20, int), surface=mesh, tolerance=0.01,
                        criteria_names=np.array(["machining_time", "scallop_max"]),
                        criteria_values=np.array([3.25, 0.0125]))
    assert plan_data(toolpath_run / "toolpath.npz")["surface"].shape == (5, 4, 3)
    assert main(["report", str(toolpath_run)]) == 0
    html = (toolpath_run / "report.html").read_text()
    traces = {t["name"]: t for t in figures(html)[1]}
    assert traces["part (toolpath.npz)"]["type"] == "surface"
    assert len(values(traces["CC points"]["x"])) == 20 and traces["CC points"]["visible"] == "legendonly"
    assert "<td>machining_time</td><td>3.25</td><td>min</td>" in html
    assert "<td>scallop_max</td><td>0.0125</td><td>mm</td>" in html


def test_a_broken_toolpath_npz_is_one_line(toolpath_run, tmp_path, capsys):
    (toolpath_run / "toolpath.npz").write_bytes(b"not a zip")
    out = tmp_path / "r.html"
    assert main(["report", str(toolpath_run), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "toolpath.npz" in err and not out.exists()


def test_problem_is_never_built(toolpath_run, monkeypatch):
    """A config.yaml naming user code is read as text: the module is never imported."""
    cfg = toolpath_run / "config.yaml"
    cfg.write_text(cfg.read_text().replace("name: kubota", "name: not_a_module_xyz:Problem"))
    assert main(["report", str(toolpath_run)]) == 0
    import sys
    assert "not_a_module_xyz" not in sys.modules


@pytest.mark.parametrize("case", ["missing", "empty", "bad_csv", "bad_apt"])
def test_bad_input_is_one_line_exit_2_no_file(case, toolpath_run, tmp_path, capsys):
    target = toolpath_run
    if case == "missing":
        target, named = tmp_path / "nope", "nope"
    elif case == "empty":
        target = tmp_path / "empty"
        target.mkdir()
        named = "not a results folder"
    elif case == "bad_csv":
        (target / "history.csv").write_text("a,b\n1,2\n")
        named = "history.csv"
    else:
        (target / "toolpath.apt").write_text("GOTO/1,2\n")
        named = "toolpath.apt"
    out = tmp_path / "out.html"
    assert main(["report", str(target), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and named in err and "Traceback" not in err
    assert not out.exists()


def test_missing_plotly_names_the_extra(kubota_run, tmp_path, capsys, monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "plotly", None)
    out = tmp_path / "r.html"
    assert main(["report", str(kubota_run), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert 'pip install "evoplan[report]"' in err and not out.exists()


