"""Reproduction scripts write outside the repository unless ``--regenerate`` is given."""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
REPRODUCE = ROOT / "runs" / "reproduce"
sys.path.insert(0, str(REPRODUCE))
from outputs import add_report_options, resolve_report_paths  # noqa: E402


def _args(argv, figures=None):
    ap = argparse.ArgumentParser()
    add_report_options(ap, figures)
    return ap.parse_args(argv)


def test_a_script_run_writes_under_the_current_directory_and_leaves_the_committed_report(tmp_path):
    report = ROOT / "runs/reproduce/vega_budget.md"
    committed = report.read_bytes()
    r = subprocess.run([sys.executable, str(REPRODUCE / "vega_budget.py"), "--seeds", "1"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    written = tmp_path / "results" / "reproduce" / report.name
    assert written.is_file() and "--seeds 1" in written.read_text()
    assert report.read_bytes() == committed


def test_regenerate_names_the_files_beside_the_script(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    script = tmp_path / "repo" / "runs" / "reproduce" / "table.py"
    figures = {"png": "table_best.png"}
    args = _args(["--regenerate"], figures)
    resolve_report_paths(args, str(script), figures)
    assert Path(args.out) == script.with_suffix(".md") and Path(args.png) == script.parent / "table_best.png"
    args = _args([], figures)
    resolve_report_paths(args, str(script), figures)
    default = Path("results/reproduce")
    assert Path(args.out) == default / script.with_suffix(".md").name and Path(args.png) == default / "table_best.png"
    mine = str(Path("x", "report").with_suffix(".md"))
    args = _args(["--out", mine, "--png", ""], figures)
    resolve_report_paths(args, str(script), figures)
    assert args.out == mine and args.png == "" and (tmp_path / "x").is_dir()


def test_every_reproduction_script_takes_its_paths_from_the_one_rule():
    scripts = sorted(p for p in REPRODUCE.glob("*.py") if p.name != "outputs.py")
    assert len(scripts) >= 8
    for script in scripts:
        text = script.read_text()
        assert 'with_suffix(".md")' not in text, f"{script.name} writes beside itself by default"
        if "resolve_report_paths" in text or "--regenerate" in text:
            continue  # a committed report, rewritten only on request
        # no committed report: nothing may be written into the script's own folder
        assert not re.search(r"(HERE|__file__)[^\n]*\.write_(text|bytes)", text), script.name
