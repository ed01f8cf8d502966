"""``evoplan run CONFIG [--out DIR] [--seed N] [--resume DIR] [--quiet]``: one optimization."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..errors import EvoplanError


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("run", help="run one optimization from a YAML file")
    p.add_argument("config", help="YAML run file, e.g. runs/kubota_vega.yaml")
    p.add_argument("--out", help="results folder (default: results/<name>-seed<N>-<time>)")
    p.add_argument("--seed", type=int, help="override the file's seed")
    p.add_argument("--resume", metavar="DIR", help="continue the run checkpointed in DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def main(args: argparse.Namespace) -> int:
    from ..runner import default_out, execute, prepare_file, resume_seed

    if args.resume and args.out:
        raise EvoplanError("give either --out (a new run) or --resume DIR (continue one), not both")
    seed = args.seed
    if args.resume and seed is None:
        seed = resume_seed(Path(args.resume))
    prepared = prepare_file(args.config, seed)
    out = Path(args.resume or args.out or default_out(prepared.config))
    state = execute(prepared, out, resume=bool(args.resume), progress=False if args.quiet else None)
    print(json.dumps({
        "out": str(out),
        "best": state.best_f,
        "evaluations": state.evaluations,
        "generations": state.algorithm.generation,
        "failures": state.failures,
        "stop_reason": state.stop_reason,
    }))
    return 0
