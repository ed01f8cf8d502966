"""``evoplan report`` on a study folder and a simulate folder (hand-written files: data only)."""

from __future__ import annotations

import json

import pytest

from evoplan.cli import main
from tests.report.test_report import figures, values

pytest.importorskip("plotly")

RUNS = """key,algorithm,problem,dimension,factor,level,repetition,seed,status,final_best
k.ga.r0,ga,kubota,2,,,0,11,ok,0.25
k.ga.r1,ga,kubota,2,,,1,12,ok,0.5
k.vega.r0,vega,kubota,2,,,0,11,ok,0.125
k.vega.r1,vega,kubota,2,,,1,12,failed,
k.ga.r0,ga,sphere,3,,,0,11,ok,2.0
"""
SUMMARY = """problem,dimension,algorithm,factor,level,runs,failed,median,best,worst,mean_rank
kubota,2,ga,,,2,0,0.375,0.25,0.5,1.5
kubota,2,vega,,,2,1,0.125,0.125,0.125,1.5
"""


def test_study_report_boxes_per_variant_and_summary(tmp_path, capsys):
    (tmp_path / "runs.csv").write_text(RUNS)
    (tmp_path / "summary.csv").write_text(SUMMARY)
    assert main(["report", str(tmp_path)]) == 0
    html = (tmp_path / "report.html").read_text()
    kubota, sphere = figures(html)
    boxes = {t["name"]: values(t["y"]) for t in kubota}
    assert boxes == {"ga": [0.25, 0.5], "vega": [0.125]}  # the failed run is not drawn
    assert "1 run(s) failed" in html
    assert [t["name"] for t in sphere] == ["ga"]
    assert "<td>vega</td>" in html and '<td class="num">0.375</td>' in html


def test_simulate_report_measures_with_units_and_figures(tmp_path, capsys):
    from PIL import Image

    record = {"plan": "p", "scallop_max_mm": 0.03, "scallop_p99_mm": 0.02, "scallop_mean_mm": 0.01,
              "gouge_max_mm": 0.0, "seconds": 1.5, "cutter": {"type": "flat", "diameter": 12.0, "corner_radius": 0.0},
              "mesh_mm": "n/a", "converged": True, "zones": [{"zone": 0, "scallop_max_mm": 0.03}]}
    (tmp_path / "simulation.json").write_text(json.dumps(record))
    Image.new("RGB", (8, 8), "red").save(tmp_path / "deviation_map.png")
    assert main(["report", str(tmp_path)]) == 0
    html = (tmp_path / "report.html").read_text()
    (bars,) = figures(html)
    assert bars[0]["x"] == ["p99", "max", "mean"] and values(bars[0]["y"]) == [0.02, 0.03, 0.01]
    assert "<td>scallop_max_mm</td><td class=\"num\">0.03</td><td>mm</td>" in html
    assert "<td>cutter.diameter</td><td class=\"num\">12</td><td>mm</td>" in html
    # a name, a flag or a text carries no unit, whatever the key's suffix says
    assert "<tr><td>cutter.type</td><td>flat</td><td></td></tr>" in html
    assert "<tr><td>mesh_mm</td><td>n/a</td><td></td></tr>" in html
    assert "<tr><td>converged</td><td>True</td><td></td></tr>" in html
    assert "<th>scallop_max_mm (mm)</th>" in html
    assert 'src="data:image/png;base64,' in html


def test_bad_simulation_json_is_one_line(tmp_path, capsys):
    (tmp_path / "simulation.json").write_text("[1, 2]")
    assert main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "simulation.json" in err and not (tmp_path / "report.html").exists()


def test_cutter_numbers_carry_their_own_units():
    from evoplan.report.simulate import flat

    rows = flat({"cutter": {"type": "tapered_ball", "diameter": 6.0, "corner_radius": 1.5, "taper_angle": 5.0}})
    assert rows == [["cutter.type", "tapered_ball", ""], ["cutter.diameter", 6.0, "mm"],
                    ["cutter.corner_radius", 1.5, "mm"], ["cutter.taper_angle", 5.0, "deg"]]


def test_a_decision_named_by_text_has_no_unit(tmp_path):
    from evoplan.report.run import best_table

    (tmp_path / "best.json").write_text(json.dumps({"variables": {"step": 0.5, "lead": "auto"}, "objective": 1.0}))
    html = best_table(tmp_path / "best.json")
    assert '<tr><td>step</td><td class="num">0.5</td><td>mm</td>' in html
    assert "<tr><td>lead</td><td>auto</td><td></td>" in html


def test_cd_labels_of_tied_variants_stack_apart():
    import itertools

    import pandas as pd

    from evoplan.report.studyfigs import CD_LINE, cd_figure, label_levels

    rows = []
    families = {"kubota": {"ga": 2.0, "vega": 2.0, "de": 2.0},                           # all tied
                "rastrigin": {"ga": 1.5, "vega": 1.5, "de": 3.5, "cmaes": 3.5, "pso": 3.5, "nsga": 3.52, "x": 6.0}}
    for problem, ranks in families.items():
        for a, b in itertools.combinations(ranks, 2):
            rows.append(dict(problem=problem, dimension=2, factor="", a=a, b=b, mean_rank_a=ranks[a],
                             mean_rank_b=ranks[b], p_nemenyi=0.5 if abs(ranks[a] - ranks[b]) < 2.5 else 0.01))
    fig = cd_figure(pd.DataFrame(rows), {})
    bars = [t for t in fig.data if t.mode == "lines"]
    top = min(t.y[0] for t in bars)
    labels = [a for a in fig.layout.annotations if (a.name or "").startswith("cd label")]
    assert len(labels) == 10
    span = 7 - 1
    for a, b in itertools.combinations(labels, 2):
        if a.name == b.name and abs(a.x - b.x) <= 0.08 * span:              # one row, labels that could touch
            # each label's line: [y - CD_LINE, y] above the marker, [y, y + CD_LINE] below
            ya = (a.y - CD_LINE, a.y) if a.yanchor == "bottom" else (a.y, a.y + CD_LINE)
            yb = (b.y - CD_LINE, b.y) if b.yanchor == "bottom" else (b.y, b.y + CD_LINE)
            assert min(ya[1], yb[1]) - max(ya[0], yb[0]) <= 0, (a.text, b.text)
    kubota = [a for a in labels if "kubota" in a.name]
    assert max(a.y for a in kubota) + CD_LINE <= top                         # above the first row's bars
    # the y axis counts pixels: the plot area (height less the margins) spans the range exactly
    lo, hi = sorted(fig.layout.yaxis.range)
    assert fig.layout.height - fig.layout.margin.t - fig.layout.margin.b == hi - lo and lo == 0
    assert label_levels([2.0, 2.0, 2.0, 2.0, 5.0], 4) == [(1, 0), (-1, 0), (1, 1), (-1, 1), (-1, 0)]
