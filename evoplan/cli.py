"""The ``evoplan`` command line.

``evoplan run CONFIG [--out DIR] [--seed N] [--resume DIR] [--quiet]``

User errors (bad YAML, unknown names, bad values, missing files) print one line
``evoplan: error: ...`` and exit with code 2, leaving no results folder behind.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from . import __version__
from .errors import EvoplanError


def _cmd_run(args: argparse.Namespace) -> int:
    from .runner import default_out, execute, prepare_file, resume_seed

    if args.resume and args.out:
        raise EvoplanError("give either --out (a new run) or --resume DIR (continue one), not both")
    seed = args.seed
    if args.resume and seed is None:
        seed = resume_seed(Path(args.resume))
    prepared = prepare_file(args.config, seed)
    out = Path(args.resume or args.out or default_out(prepared.config))
    state = execute(prepared, out, resume=bool(args.resume), progress=False if args.quiet else None)
    summary = {
        "out": str(out),
        "best": state.best_f,
        "evaluations": state.evaluations,
        "generations": state.algorithm.generation,
        "failures": state.failures,
        "stop_reason": state.stop_reason,
    }
    print(json.dumps(summary))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="evoplan", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"evoplan {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run one optimization from a YAML file")
    run.add_argument("config", help="YAML run file, e.g. runs/kubota_vega.yaml")
    run.add_argument("--out", help="results folder (default: results/<name>-seed<N>-<time>)")
    run.add_argument("--seed", type=int, help="override the file's seed")
    run.add_argument("--resume", metavar="DIR", help="continue the run checkpointed in DIR")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(func=_cmd_run)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except EvoplanError as e:
        print(f"evoplan: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("evoplan: interrupted (the last checkpoint can be resumed with --resume)", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
