"""``evoplan report``: the kind of each folder, one self-contained file, bad input in one line."""

from __future__ import annotations

import re

import numpy as np
import pytest

from evoplan.cli import main
from evoplan.report.decimate import decimate_runs, fit_budget

from .synth import synth  # noqa: F401 - the fixture


@pytest.mark.parametrize("kind", ["run", "toolpath_run", "pareto_run", "study", "simulation", "machine"])
def test_each_folder_gives_one_self_contained_page(synth, kind, capsys):
    out = synth[kind] / "report.html"
    assert main(["report", str(synth[kind])]) == 0
    html = out.read_text()
    assert capsys.readouterr().out.strip() == str(out)
    assert html.startswith("<!DOCTYPE html>") and "Plotly.newPlot" in html
    # no external script, stylesheet, image or font: everything is inlined
    assert not re.search(r"<(script|link|img)[^>]+(src|href)=", html)


def test_bad_folders_get_one_line_and_exit_2(tmp_path, capsys):
    assert main(["report", str(tmp_path / "missing")]) == 2
    assert main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and all(line.startswith("evoplan: error: ") for line in err)
    assert str(tmp_path / "missing") in err[0] and "summary.json" in err[1]
    assert not list(tmp_path.iterdir())


def _distance_to_polyline(p, q):
    """Distance of each point p to the polyline q (segments q[i] -> q[i+1])."""
    a, b = q[:-1], q[1:]
    d = b - a
    t = np.clip(np.einsum("pij,ij->pi", p[:, None] - a[None], d) / np.maximum((d * d).sum(1), 1e-300), 0, 1)
    closest = a[None] + t[..., None] * d[None]
    return np.linalg.norm(p[:, None] - closest, axis=2).min(axis=1)


def test_decimation_stays_within_its_tolerance():
    rng = np.random.default_rng(3)
    t = np.linspace(0, 60, 3000)
    p = np.c_[t, 4 * np.sin(t / 3), np.cos(t) + 0.01 * rng.standard_normal(len(t))]
    run = np.minimum(t // 20, 2).astype(int)
    for tol in (0.005, 0.05, 0.5):
        keep = decimate_runs(p, run, tol)
        assert keep.sum() < len(p)
        for r in np.unique(run):
            sel = run == r
            kept = p[sel & keep]
            assert keep[np.flatnonzero(sel)[[0, -1]]].all()           # both ends kept
            assert _distance_to_polyline(p[sel], kept).max() <= tol + 1e-12
    keep, tol = fit_budget(p, run, 200)
    assert keep.sum() <= 200 and tol >= 0.005


@pytest.mark.parametrize("watch", [[], ["--watch", "--timeout", "1"]])
def test_out_naming_a_folder_is_one_line_and_exit_2(synth, tmp_path, capsys, watch):
    out = tmp_path / "existing"
    out.mkdir()
    assert main(["report", str(synth["run"]), "--out", str(out), *watch]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(out) in err and "--out" in err and "folder" in err
    assert "Traceback" not in err and list(out.iterdir()) == []


def test_help_names_every_folder_kind(capsys):
    with pytest.raises(SystemExit):
        main(["report", "-h"])
    text = " ".join(capsys.readouterr().out.split())
    assert "DIR a run, study, simulate or machine results folder" in text
    assert "machine folder (summary.json)" in text


def layouts(html: str) -> dict:
    """Each plotly figure's layout embedded in the page, by its ``meta`` name."""
    import json

    out, decoder = {}, json.JSONDecoder()
    for m in re.finditer(r'Plotly\.newPlot\(\s*"[^"]+",\s*', html):
        _, end = decoder.raw_decode(html, m.end())                      # the data array
        layout, _ = decoder.raw_decode(html, html.index("{", end))
        out[layout.get("meta", "")] = layout
    return out


@pytest.mark.parametrize("kind, names", [("machine", ["operations3d"]), ("toolpath_run", ["toolpath3d"]),
                                         ("simulation", ["deviation3d"])])
def test_3d_legends_sit_under_the_scene_not_over_an_axis(synth, kind, names):
    assert main(["report", str(synth[kind])]) == 0
    found = layouts((synth[kind] / "report.html").read_text())
    for name in names:
        legend = found[name]["legend"]
        # one row under the plot area (y = 0 is its bottom edge, the legend hangs from it):
        # outside the scene, whose Z axis this camera draws on the left
        assert legend["orientation"] == "h" and legend["yanchor"] == "top" and legend["y"] <= 0
        assert legend["x"] == 0 and legend["xanchor"] == "left"
        assert "domain" not in found[name].get("scene", {})              # the scene keeps the whole area
