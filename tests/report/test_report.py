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
    assert "zone 0 pass 0" in html and "zone 0 pass 1" in html
    assert "8 points in 2 sections, 2 rapid moves, tool D10 r0 mm" in html
    traces = {t["name"]: t for t in figures(html)[1]}
    assert set(traces) == {"zone 0 pass 0", "zone 0 pass 1", "rapids"}
    rapids = traces["rapids"]
    assert rapids["line"]["dash"] == "dash"
    # the rapid out of pass 0: from its last point (20, 0, 2) up to (20, 5, 20)
    assert [values(rapids[k])[:3] for k in "xyz"] == [[20, 20, None], [0, 5, None], [2, 20, None]]
    assert values(traces["zone 0 pass 1"]["x"]) == [20, 10, 0]
    assert values(traces["zone 0 pass 0"]["x"])[:4] == [0, 10, 20, None]  # broken before the rapid


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


def test_decimation_keeps_every_dropped_point_within_the_tolerance():
    from evoplan.report.run import decimate, deviation

    rng = np.random.default_rng(3)
    x = np.linspace(0, 100, 5001)
    tip = np.column_stack([x, 5 * np.sin(x / 7), 0.0003 * rng.standard_normal(x.size)])
    rapid = np.zeros(x.size, bool)
    rapid[2500] = True  # a rapid move into point 2500: both of its ends stay
    section = (x > 60).astype(int)
    keep = decimate(tip, rapid, section, 0.01)
    assert keep.sum() < x.size / 4  # the smooth curve needs far fewer points
    assert keep[[0, 2499, 2500, -1]].all()
    first = np.flatnonzero(section == 1)[0]
    assert keep[first - 1] and keep[first]  # section ends stay
    # distance of every original point to the drawn polyline (segments of kept neighbours)
    k = np.flatnonzero(keep)
    seg = np.searchsorted(k, np.arange(x.size), side="right") - 1
    seg = np.clip(seg, 0, len(k) - 2)
    a, b = tip[k[seg]], tip[k[seg + 1]]
    ab = b - a
    t = np.clip(((tip - a) * ab).sum(1) / (ab * ab).sum(1), 0, 1)
    dist = np.linalg.norm(a + t[:, None] * ab - tip, axis=1)
    assert dist.max() <= 0.01
    assert deviation(tip, keep) == pytest.approx(dist.max())
    assert deviation(tip, np.ones(x.size, bool)) == 0.0
    assert decimate(tip, rapid, section, 0.0).all()  # no tolerance, nothing dropped
