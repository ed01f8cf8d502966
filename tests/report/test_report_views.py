"""The report's 3D, deviation, Pareto, ECDF/CD and machine figures in a real browser (headless Chromium over the DevTools protocol): it
opens with no console error and no network request, its 3D canvas is not blank, and a legend
click changes what is shown (the trace's visibility and the screenshot's pixels)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from evoplan.report import build

from .cdp import chromium, shots_dir
from .synth import synth  # noqa: F401 - the fixture

pytestmark = pytest.mark.skipif(chromium() is None, reason="no chromium on PATH (.ci/run installs it)")

KINDS = ["pareto_run", "study", "simulation", "machine"]


@pytest.mark.parametrize("kind", KINDS)
def test_report_opens_draws_and_reacts(synth, browser, kind):
    browser.events.clear()
    browser.show(build(synth[kind]))
    assert browser.js("document.title").endswith(f": {synth[kind].resolve().name}")  # this folder's page
    browser.js("document.querySelectorAll('.js-plotly-plot').forEach((g, i) => g.id = 'plot' + i)")
    assert browser.errors() == []
    assert [u for u in browser.requests() if not u.startswith(("file:", "data:"))] == []
    shots = shots_dir()
    fig = browser.js("[...document.querySelectorAll('.js-plotly-plot')].find(g => g.querySelector('.legend .traces')).id")
    first = browser.screenshot(f"#{fig}", shots / f"{kind}_fig0.png")
    # not blank: a drawn figure has many distinct colours and spread, a blank one is uniform
    gray = first.mean(axis=2)
    assert gray.std() > 15 and len(np.unique(first.reshape(-1, 3), axis=0)) > 200
    if browser.js(f"!!document.querySelector('#{fig} canvas')"):     # a 3D (WebGL) figure: its middle drawn
        h, w = gray.shape
        middle = first[h // 4: 3 * h // 4, w // 4: 3 * w // 4]
        assert middle.std() > 10 and len(np.unique(middle.reshape(-1, 3), axis=0)) > 100
    # a legend click toggles the first trace that has a legend entry
    before = browser.js(f"document.getElementById('{fig}')._fullData.map(t => t.visible)")
    box = browser.box(f"#{fig} .legend .traces .legendtoggle")
    browser.click(box["x"] + box["w"] / 2, box["y"] + box["h"] / 2)
    visible = f"document.getElementById('{fig}')._fullData.map(t => t.visible)"
    browser.wait_for(f"JSON.stringify({visible}) !== {json.dumps(json.dumps(before, separators=(',', ':')))}")
    after = browser.js(visible)
    assert after != before
    second = browser.screenshot(f"#{fig}", shots / f"{kind}_fig0_clicked.png")
    assert second.shape == first.shape and np.abs(second.astype(int) - first.astype(int)).sum() > 0
    assert browser.errors() == []


def test_hover_shows_a_points_decisions(synth, browser):
    browser.events.clear()
    browser.show(build(synth["pareto_run"]))
    browser.js("document.querySelectorAll('.js-plotly-plot').forEach((g, i) => g.id = 'plot' + i)")
    div = browser.js("[...document.querySelectorAll('.js-plotly-plot')].find(g => g._fullData.some(t => "
                     "t.marker && t.marker.symbol === 'star')).id")
    # the star (Eq. 9's choice) in page coordinates, from plotly's own axes
    xy = browser.js(f"(()=>{{const g=document.getElementById('{div}');const t=g._fullData.find(t=>t.marker&&"
                    "t.marker.symbol==='star');const xa=g._fullLayout.xaxis, ya=g._fullLayout.yaxis;"
                    "g.scrollIntoView({block:'center'});const r=g.getBoundingClientRect();"
                    "return [r.x+xa._offset+xa.l2p(t.x[0]), r.y+ya._offset+ya.l2p(t.y[0])];})()")
    browser.js(f"document.getElementById('{div}').scrollIntoView({{block:'center'}})")
    xy = browser.js(f"(()=>{{const g=document.getElementById('{div}');const t=g._fullData.find(t=>t.marker&&"
                    "t.marker.symbol==='star');const xa=g._fullLayout.xaxis, ya=g._fullLayout.yaxis;"
                    "const r=g.getBoundingClientRect();"
                    "return [r.x+xa._offset+xa.l2p(t.x[0]), r.y+ya._offset+ya.l2p(t.y[0])];})()")
    assert browser.js(f"document.querySelector('#{div} .hoverlayer').textContent") == ""
    browser.mouse("mouseMoved", xy[0], xy[1])
    browser.wait_for(f"document.querySelector('#{div} .hoverlayer').textContent !== ''", timeout=5)
    text = browser.js(f"document.querySelector('#{div} .hoverlayer').textContent")
    assert "stepover (% of D): 35" in text and "machining_time (min)" in text
    assert browser.errors() == []
