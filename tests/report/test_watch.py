"""``evoplan report DIR --watch``: served on 127.0.0.1, the version moves as history.csv grows,
and it stops by itself when the run ends (best.json written) or at --timeout."""

from __future__ import annotations

import re
import shutil
import threading
import time
import urllib.request

import pytest

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


@pytest.mark.parametrize("value", ["99999", "-1", "http"])
def test_a_bad_port_is_one_usage_line_before_anything_is_served(value, synth, capsys):
    from evoplan.cli import main

    with pytest.raises(SystemExit) as stop:
        main(["report", str(synth["run"]), "--watch", "--port", value, "--timeout", "1"])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1 and "--port" in err and value in err
    assert "Traceback" not in err and "serving" not in err


def test_a_port_in_use_is_one_line_naming_it(synth, tmp_path, capsys):
    import socket

    from evoplan.cli import main

    out = tmp_path / "r.html"
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        code = main(["report", str(synth["run"]), "--watch", "--port", str(port), "--timeout", "1",
                     "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and f"--port {port}" in err and "Traceback" not in err
    assert not out.exists()
