"""A study cell whose worker dies, or whose evaluation hangs past ``timeout_s``, costs that
cell (or those rows), not the study: on processes and Dask, reproducibly, with the numbers of a
study whose same rows fail cleanly."""

from __future__ import annotations

import pandas as pd
import pytest

from evoplan.cli import main

from .workers import evoplan, runs_table, study_file


@pytest.fixture(scope="module")
def clean_study(tmp_path_factory):
    """The reference study whose bad rows fail cleanly, shared by the study tests."""
    root = tmp_path_factory.mktemp("clean_study")
    assert main(["study", str(study_file(root, "Fails", "ref")), "--out", str(root / "ref"), "--quiet"]) == 0
    return runs_table(root / "ref")


def test_a_study_cell_whose_worker_dies_fails_alone_and_reproducibly(tmp_path, clean_study):
    cfg = study_file(tmp_path, "Dies", "dies")
    runs = []
    for backend in ("processes", "processes", "dask"):
        out = tmp_path / f"dies-{len(runs)}"
        proc = evoplan("study", cfg, "--out", out, "--backend", backend, "--workers", 2)
        assert "Traceback" not in proc.stderr, proc.stderr
        runs.append(runs_table(out))
    expected = clean_study
    for r in runs:
        pd.testing.assert_frame_equal(r, runs[0])
    died = runs[0].status != "ok"
    assert died.sum() >= 1 and runs[0].index[died].str.startswith("p.").all()
    assert (runs[0].error[died].str.contains("worker died")).all()
    # every cell whose worker did not die has the numbers of the clean study
    ok = runs[0].index[~died]
    pd.testing.assert_frame_equal(runs[0].loc[ok].drop(columns="error"), expected.loc[ok].drop(columns="error"),
                                  check_dtype=False)


@pytest.mark.parametrize("backend", ["processes", "dask"])
def test_a_study_bounds_a_hanging_evaluation_with_timeout_s(tmp_path, clean_study, backend):
    cfg = study_file(tmp_path, "Hangs", "hangs", "evaluation: {timeout_s: 0.3}\n")
    proc = evoplan("study", cfg, "--out", tmp_path / "hangs", "--backend", backend, "--workers", 2)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    got, expected = runs_table(tmp_path / "hangs"), clean_study
    assert (got.status == "ok").all() and got.failures.sum() > 0
    pd.testing.assert_frame_equal(got, expected)
