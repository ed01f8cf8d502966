"""The report opened in a real browser (headless Chromium over the DevTools protocol,
``cdp.py``): it renders offline, plots drawn.

Skipped when Debian's ``chromium`` is not installed (``.ci/run`` installs it when run as root).
The Chromium is the session's (``conftest.browser``), shared with ``test_report_views.py``.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from evoplan.cli import main

from .cdp import chromium

pytest.importorskip("plotly")
pytest.importorskip("PIL.Image")
pytestmark = pytest.mark.skipif(chromium() is None, reason="chromium is not installed "
                                "(apt-get install chromium; .ci/run does it as root)")


def test_console_check_sees_a_page_error(browser, tmp_path):
    """The errors the report tests read do carry a page's uncaught errors."""
    page = tmp_path / "bad.html"
    page.write_text("<html><body><script>undefined_function();</script></body></html>")
    browser.events.clear()
    browser.open(page.as_uri(), ready="true")
    assert any("ReferenceError" in e and "undefined_function" in e for e in browser.errors())


def test_run_report_renders_offline(toolpath_run, tmp_path, browser):
    out = tmp_path / "report.html"
    assert main(["report", str(toolpath_run), "--out", str(out)]) == 0
    html = out.read_text()
    # no request can leave the page: no external script, stylesheet, image or frame
    assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)\s*=\s*[\"']?(https?:)?//", html)
    assert not re.search(r"<script[^>]+src=", html)
    browser.events.clear()
    browser.viewport(1200, 1900)
    try:
        browser.show(html)                                                # the file the command wrote
        image = browser.screenshot().astype(float)
    finally:
        browser.viewport()
    assert browser.errors() == []  # no script error on the page
    assert [u for u in browser.requests() if not u.startswith(("file:", "data:"))] == []  # nothing requested
    assert image.shape[:2] == (1900, 1200)
    # not blank: the page is mostly white, but the plots put many distinct colours on it
    assert image.std() > 10
    colours = np.unique(image.reshape(-1, 3).astype(np.uint8), axis=0)
    assert len(colours) > 200
    # the convergence plot drew its best-so-far line (plotly's #D55E00) into the first screen
    top = image[:900]
    orange = (np.abs(top - [0xD5, 0x5E, 0x00]).sum(axis=2) < 40).sum()
    assert orange > 300
    # the 3D scene drew zone 0's passes below it (the Blues scale, a shade per pass)
    low = image[900:]
    blue = (low[..., 2] - low[..., 0] > 60) & (low[..., 2] > 90)
    assert blue.sum() > 50
