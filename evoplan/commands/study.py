"""``evoplan study STUDY [--out DIR] [--set KEY.PATH=VALUE ...] [--backend serial|processes|dask] [--workers N]
[--scheduler ADDR]``."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..errors import EvoplanError
from ..overrides import add_argument
from . import COMMANDS

BACKENDS = ("serial", "processes", "dask")  # evoplan.parallel.POOLS, named without importing it (numpy)

FAILED_RUNS = 3  # exit code of a study that finished with failed runs (documented in docs/robustness.md)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("study", help=COMMANDS["study"])
    p.add_argument("study", help="YAML study file, e.g. runs/compare_benchmarks.yaml")
    p.add_argument("--out", help="results folder (default: results/<study name>); "
                                 "an unfinished study there is resumed")
    p.add_argument("--backend", choices=BACKENDS, help="where the runs execute (default: serial; "
                                                          "dask when --scheduler is given)")
    p.add_argument("--workers", type=int, help="worker processes (default: one per CPU)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler, e.g. tcp://10.0.0.5:8786 "
                                                          "(default with --backend dask: a local cluster)")
    add_argument(p, "--set seeds=5 --set budget.evaluations=500")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def main(args: argparse.Namespace) -> int:
    from ..config import read_yaml
    from ..overrides import apply_settings
    from ..study.config import parse_study
    from ..study.runner import run_study

    backend = args.backend or ("dask" if args.scheduler else "serial")
    if args.scheduler and backend != "dask":
        raise EvoplanError(f"--scheduler is for --backend dask, not {backend}")
    if args.workers is not None and args.workers < 1:
        raise EvoplanError(f"--workers must be at least 1, got {args.workers}")
    data = apply_settings(read_yaml(args.study), args.settings, str(args.study))
    data.setdefault("name", Path(args.study).stem)
    study = parse_study(data, str(args.study))
    out = Path(args.out or Path("results") / study.name)
    summary = run_study(study, args.study, out, backend, args.workers, args.scheduler,
                        progress=False if args.quiet else None)
    print(json.dumps(summary))
    if summary["failed"]:  # the study is written, but not all of it ran: say so in the exit code
        print(f"evoplan: {summary['failed']} of {summary['ran']} runs failed (runs.csv, column error); "
              f"their variants are left out of the tests and figures", file=sys.stderr)
        return FAILED_RUNS
    return 0
