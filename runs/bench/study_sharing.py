"""Seconds per run of a study with and without the shared problem (evoplan/study/shared.py).

Runs the same study twice in this process, serially: once with every run building its own
problem (what studies did before), once with the worker-level memo; prints each run's wall
seconds (runs.csv) and checks that both give the same numbers.

    python runs/bench/study_sharing.py [STUDY] [--set KEY=VALUE ...] [--out /tmp/study_sharing]

Default: runs/choi_toolpath_vega_vs_ga.yaml --set seeds=3 --set budget.evaluations=40.
Not a test: it prints measured figures (say whether the host was shared).
"""

from __future__ import annotations

import argparse
import shutil
from pathlib import Path

import numpy as np
import pandas as pd

from evoplan.config import read_yaml
from evoplan.overrides import apply_settings
from evoplan.study import shared
from evoplan.study.config import parse_study
from evoplan.study.runner import run_study


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study", nargs="?", default="runs/choi_toolpath_vega_vs_ga.yaml")
    ap.add_argument("--set", action="append", default=None, dest="sets")
    ap.add_argument("--out", default="/tmp/study_sharing")
    args = ap.parse_args()
    sets = args.sets or ["seeds=3", "budget.evaluations=40", "output.plots=false"]
    data = apply_settings(read_yaml(args.study), sets, args.study)
    data.setdefault("name", Path(args.study).stem)
    study = parse_study(data, args.study)
    out = Path(args.out)
    shutil.rmtree(out, ignore_errors=True)
    tables = {}
    for mode in ("fresh", "shared"):
        shared.clear()
        saved = shared.SHARED
        if mode == "fresh":
            shared.SHARED = frozenset()
        try:
            run_study(study, args.study, out / mode, "serial", progress=False)
        finally:
            shared.SHARED = saved
        tables[mode] = pd.read_csv(out / mode / "runs.csv")
        s = tables[mode]["wall_seconds"].to_numpy()
        print(f"{mode:6s}: seconds per run {' '.join(f'{x:.2f}' for x in s)}; first {s[0]:.2f}, "
              f"median after the first {np.median(s[1:]):.2f}; problems built {shared.STATS['built']}, "
              f"reused {shared.STATS['reused']}")
    same = tables["fresh"].drop(columns="wall_seconds").equals(tables["shared"].drop(columns="wall_seconds"))
    print(f"same runs.csv numbers: {same}")


if __name__ == "__main__":
    main()
