"""A run whose worker dies or hangs goes on, with the numbers of a run whose same rows fail
cleanly (``Fails`` returns NaN where ``Dies`` exits and ``Hangs`` sleeps)."""

from __future__ import annotations

import pandas as pd
import pytest

from evoplan.cli import main

from .workers import evoplan, results, run_file


@pytest.mark.parametrize("backend,problem,timeout", [("processes", "Dies", None), ("processes", "Hangs", 0.5),
                                                     ("dask", "Dies", None)])
def test_a_run_goes_on_with_the_numbers_of_clean_failures(tmp_path, clean_run, backend, problem, timeout):
    extra = f"evaluation: {{backend: {backend}, workers: 2" + (f", timeout_s: {timeout}" if timeout else "") + "}\n"
    cfg = run_file(tmp_path, problem, "bad", extra)
    proc = evoplan("run", cfg, "--out", tmp_path / "bad", "--quiet")
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    h1, b1 = results(tmp_path / "bad")
    h2, b2 = results(clean_run)
    pd.testing.assert_frame_equal(h1, h2)
    assert b1 == b2 and b1["failures"] > 0


@pytest.fixture(scope="module")
def clean_run(tmp_path_factory):
    """The reference run whose bad rows fail cleanly (NaN), shared by the run tests (in-process:
    nothing misbehaves in it)."""
    root = tmp_path_factory.mktemp("clean_run")
    assert main(["run", str(run_file(root, "Fails", "ref")), "--out", str(root / "ref"), "--quiet"]) == 0
    return root / "ref"
