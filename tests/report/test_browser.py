"""The report opened in a real browser (headless Chromium): it renders offline, plots drawn.

Skipped when Debian's ``chromium`` is not installed (``.ci/run`` installs it when run as root).
"""

from __future__ import annotations

import re
import shutil
import subprocess

import numpy as np
import pytest

from evoplan.cli import main

pytest.importorskip("plotly")
PIL = pytest.importorskip("PIL.Image")
CHROMIUM = shutil.which("chromium")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed "
                                "(apt-get install chromium; .ci/run does it as root)")


def screenshot(html, png, height=900) -> tuple[np.ndarray, str]:
    """Chromium's screenshot of ``html`` as an (h, w, 3) array, and its console log (stderr);
    plots get 5 s of virtual time."""
    cmd = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-logging=stderr",
           "--v=0", f"--screenshot={png}",
           f"--window-size=1200,{height}", "--virtual-time-budget=5000", "--hide-scrollbars",
           f"--user-data-dir={png.parent / 'profile'}", html.resolve().as_uri()]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=60, check=True)
    return np.asarray(PIL.open(png).convert("RGB"), dtype=float), done.stderr


def test_console_check_sees_a_page_error(tmp_path):
    """The log the report test reads does carry a page's uncaught errors."""
    page = tmp_path / "bad.html"
    page.write_text("<html><body><script>undefined_function();</script></body></html>")
    _, log = screenshot(page, tmp_path / "bad.png", height=200)
    assert "Uncaught ReferenceError" in log


def test_run_report_renders_offline(toolpath_run, tmp_path):
    out = tmp_path / "report.html"
    assert main(["report", str(toolpath_run), "--out", str(out)]) == 0
    html = out.read_text()
    # no request can leave the page: no external script, stylesheet, image or frame
    assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)\s*=\s*[\"']?(https?:)?//", html)
    assert not re.search(r"<script[^>]+src=", html)
    image, log = screenshot(out, tmp_path / "shot.png", height=1900)
    assert "Uncaught" not in log  # no script error on the page
    assert "net::ERR" not in log and "Failed to load resource" not in log  # nothing requested
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
