"""How long a report page takes to open in headless Chromium: a toolpath run whose APT program
is about 20 MB against the same run with an 8-point program, and a page holding plotly alone.

Each page is written by ``evoplan report`` into a temporary folder (nothing in the repository),
then opened ``--repeat`` times in one Chromium (SwiftShader WebGL, as the browser tests use);
a page is open when every plotly figure on it is drawn (``tests/report/cdp.py``). The ratio of
the large page to the 8-point page says what the data costs beyond the browser's own start-up
of a 3D figure; the plotly-only page says what parsing the inlined plotly.js costs.

    python runs/bench/report_open.py [--mb 20] [--repeat 5]

Not a test: it prints measured figures. Needs Debian's chromium and the ``report`` extra.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the browser driver of the tests (tests/report/cdp.py)


def _run_folder(base: Path, name: str, passes: int, per_pass: int) -> Path:
    """A Kubota run's files plus a synthetic toolpath.apt of ``passes`` x ``per_pass`` points."""
    import evoplan
    from tests.report.synth import write_apt

    src = base / "kubota"
    if not src.exists():
        evoplan.minimize("kubota", "ga", termination={"generations": 5}, seed=1, population=10, out=src)
    out = base / name
    shutil.copytree(src, out)
    write_apt(out / "toolpath.apt", passes=passes, per_pass=per_pass)
    return out


def _page(folder: Path) -> Path:
    from evoplan.cli import main

    page = folder / "report.html"
    t0 = time.perf_counter()
    assert main(["report", str(folder), "--out", str(page)]) == 0
    print(f"  {folder.name}: toolpath.apt {(folder / 'toolpath.apt').stat().st_size / 1e6:.1f} MB, "
          f"report.html {page.stat().st_size / 1e6:.1f} MB, written in {time.perf_counter() - t0:.2f} s")
    return page


def _plotly_only(base: Path) -> Path:
    """A page with plotly.js inlined and one 2D figure of 8 points (the parse cost alone)."""
    import plotly.graph_objects as go

    page = base / "plotly_only.html"
    go.Figure(go.Scatter(x=list(range(8)), y=list(range(8)))).write_html(page, include_plotlyjs=True)
    return page


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mb", type=float, default=20.0, help="size of the large APT program (MB)")
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    from tests.report.cdp import Browser, chromium

    if chromium() is None:
        print("no chromium on PATH (apt-get install chromium)")
        return 1
    print(f"load average {os.getloadavg()[0]:.2f}")
    base = Path(tempfile.mkdtemp(prefix="evoplan-report-open-"))
    try:
        per_pass = 2000
        passes = max(1, round(a.mb * 1e6 / (per_pass * 57)))  # about 57 bytes per GOTO line
        pages = {"large": _page(_run_folder(base, "large", passes, per_pass)),
                 "8 points": _page(_run_folder(base, "small", 2, 4)),
                 "plotly only": _plotly_only(base)}
        times = {k: [] for k in pages}
        with Browser() as b:
            for _ in range(a.repeat):  # interleaved, so a change of load hits every page alike
                for k, page in pages.items():
                    b.call("Page.navigate", url="about:blank")
                    times[k].append(b.open(page.as_uri(), timeout=120))
        for k, t in times.items():
            print(f"{k:12s} open: median {statistics.median(t):.2f} s (min {min(t):.2f}, max {max(t):.2f}) "
                  f"over {len(t)}")
        ratio = [x / y for x, y in zip(times["large"], times["8 points"])]
        print(f"large / 8 points: median {statistics.median(ratio):.2f}x")
        print(f"load average {os.getloadavg()[0]:.2f}")
    finally:
        shutil.rmtree(base, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
