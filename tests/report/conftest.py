"""Small results folders for the report tests: a real kubota run, a hand-written toolpath run."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from evoplan.cli import main

ROOT = Path(__file__).resolve().parents[2]

#: two passes of 3 points, each entered by a rapid, as apt_write lays them out
APT = """PARTNO/TEST
UNITS/MM
LOADTL/1
CUTTER/10.0000,0.0000
MULTAX/ON
RAPID
GOTO/0,0,20,0,0,1
$$ ZONE 0 PASS 0
FEDRAT/1000,MMPM
GOTO/0,0,0,0,0,1
GOTO/10,0,1,0,0,1
GOTO/20,0,2,0,0,1
RAPID
GOTO/20,5,20,0,0,1
$$ ZONE 0 PASS 1
GOTO/20,5,2,0,0,1
GOTO/10,5,1,0,0,1
GOTO/0,5,0,0,0,1
FINI
"""


@pytest.fixture(scope="session")
def browser():
    """One headless Chromium for every browser test of a process (tests/report/cdp.py): it keeps
    plotly.js compiled for the page URL that ``Browser.show`` reuses."""
    pytest.importorskip("websocket")
    from .cdp import Browser, chromium

    if chromium() is None:
        pytest.skip("no chromium on PATH (.ci/run installs it)")
    with Browser() as b:
        yield b


@pytest.fixture(scope="session")
def kubota_run(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("runs") / "kubota"
    assert main(["run", str(ROOT / "runs" / "kubota_ga.yaml"), "--out", str(out), "--quiet",
                 "--set", "termination.generations=8"]) == 0
    return out


@pytest.fixture()
def toolpath_run(kubota_run, tmp_path) -> Path:
    """The kubota run's files plus a toolpath.apt: the report reads files, not the problem."""
    out = tmp_path / "toolpath"
    shutil.copytree(kubota_run, out)
    (out / "toolpath.apt").write_text(APT)
    return out
