"""Seconds to re-run a finished study: its whole analysis, and only what changed (study/memo.py).

Runs the study once into ``--out`` (outside the repository), then, interleaved over
``--repeat`` rounds in this process, re-runs it with every cell done: once with
``analysis.json`` removed (every figure and ``bayes.csv`` made again, what a re-run did
before the memo) and once with it (nothing changed, so nothing is rebuilt). Prints the
medians of wall and process CPU seconds and checks that both give the same files.

    python runs/bench/study_reanalysis.py [STUDY] [--set KEY=VALUE ...] [--repeat 3]

Default: runs/compare_benchmarks.yaml --set seeds=2 --set budget.evaluations=50 (154 runs).
Not a test: it prints measured figures (say whether the host was shared).
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import time
from pathlib import Path

from evoplan.config import read_yaml
from evoplan.overrides import apply_settings
from evoplan.study.config import parse_study
from evoplan.study.memo import FILE
from evoplan.study.runner import run_study

OUTPUTS = ("bayes.csv", "figures/convergence.png", "figures/final_values.png", "figures/ecdf.png",
           "figures/critical_difference.png")


def rerun(study, source: str, out: Path, memo: bool) -> tuple[float, float, dict[str, bytes]]:
    if not memo:
        (out / FILE).unlink(missing_ok=True)
    w0, c0 = time.perf_counter(), time.process_time()
    execution = run_study(study, source, out, "serial", progress=False)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    assert execution["ran"] == 0, execution
    return wall, cpu, {n: (out / n).read_bytes() for n in OUTPUTS if (out / n).is_file()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study", nargs="?", default="runs/compare_benchmarks.yaml")
    ap.add_argument("--set", action="append", default=None, dest="sets")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default="/tmp/study_reanalysis")
    args = ap.parse_args()
    sets = args.sets or ["seeds=2", "budget.evaluations=50"]
    data = apply_settings(read_yaml(args.study), sets, args.study)
    data.setdefault("name", Path(args.study).stem)
    study = parse_study(data, args.study)
    out = Path(args.out)
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.perf_counter()
    execution = run_study(study, args.study, out, "serial", progress=False)
    print(f"first run: {execution['ran']} runs and the analysis in {time.perf_counter() - t0:.1f} s wall")
    times = {False: [], True: []}
    files = {}
    for _ in range(args.repeat):
        for memo in (False, True):
            wall, cpu, files[memo] = rerun(study, args.study, out, memo)
            times[memo].append((wall, cpu))
    for memo, label in ((False, "whole analysis again"), (True, "only what changed (nothing)")):
        wall = statistics.median(w for w, _ in times[memo])
        cpu = statistics.median(c for _, c in times[memo])
        print(f"re-run, {label:28s}: median {wall:.2f} s wall, {cpu:.2f} s CPU")
    ratio = statistics.median(a[1] / b[1] for a, b in zip(times[False], times[True]))
    print(f"CPU ratio (whole / memo), median over rounds: {ratio:.1f}x; same files: {files[False] == files[True]}")


if __name__ == "__main__":
    main()
