"""``evoplan report DIR --watch``: served on 127.0.0.1, the version moves as history.csv grows,
and it stops by itself when the run ends (best.json written) or at --timeout."""

from __future__ import annotations

import re
import shutil
import threading
import time
import urllib.request

from evoplan.report.watch import serve

from .synth import synth  # noqa: F401 - the fixture


def test_watch_refreshes_and_stops_when_the_run_ends(synth, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(synth["run"], run)
    best = (run / "best.json").read_bytes()
    (run / "best.json").unlink()
    history = (run / "history.csv").read_text().splitlines()
    (run / "history.csv").write_text("\n".join(history[:4]) + "\n")
    urls, result = [], {}
    t = threading.Thread(target=lambda: result.setdefault("reason", serve(run, 0, 60, poll=0.2,
                                                                          announce=urls.append)))
    t.start()
    while not urls:
        time.sleep(0.05)
    url = re.search(r"http://127\.0\.0\.1:\d+/", urls[0]).group(0)
    page = urllib.request.urlopen(url, timeout=10).read().decode()
    assert "/version" in page and "Plotly" in page
    v0 = urllib.request.urlopen(url + "version", timeout=10).read()
    (run / "history.csv").write_text("\n".join(history) + "\n")          # the run goes on
    deadline = time.monotonic() + 20
    while urllib.request.urlopen(url + "version", timeout=10).read() == v0:
        assert time.monotonic() < deadline, "the version never moved"
        time.sleep(0.1)
    (run / "best.json").write_bytes(best)                                # the run ends
    t.join(30)
    assert not t.is_alive() and result["reason"] == "finished"


def test_watch_stops_at_its_timeout(synth, tmp_path):
    run = tmp_path / "run"
    shutil.copytree(synth["run"], run)
    (run / "best.json").unlink()
    t0 = time.monotonic()
    assert serve(run, 0, 1.0, poll=0.1, announce=lambda m: None) == "timeout"
    assert time.monotonic() - t0 < 10
