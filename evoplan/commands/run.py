"""``evoplan run CONFIG [--out DIR] [--seed N] [--set KEY.PATH=VALUE ...] [--resume DIR] [--quiet]``."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..errors import EvoplanError
from ..overrides import add_argument
from . import COMMANDS


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("run", help=COMMANDS["run"])
    p.add_argument("config", help="YAML run file, e.g. runs/kubota_vega.yaml (see: evoplan examples)")
    p.add_argument("--out", help="results folder (default: results/<name>-seed<N>-<time>)")
    p.add_argument("--seed", type=int, help="override the file's seed")
    add_argument(p)
    p.add_argument("--resume", metavar="DIR", help="continue the run checkpointed in DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def load(path: str, seed: int | None, settings: list[str]):
    """The validated configuration of a run file with ``--seed`` and ``--set`` applied."""
    from ..config import parse_config, read_yaml
    from ..overrides import apply_settings

    data = apply_settings(read_yaml(path), settings, str(path))
    if seed is not None:
        data["seed"] = seed
    data.setdefault("name", Path(path).stem)
    return parse_config(data, str(path))


def main(args: argparse.Namespace) -> int:
    from ..runner import default_out, execute, prepare, resume_seed, resume_state

    if args.resume and args.out:
        raise EvoplanError("give either --out (a new run) or --resume DIR (continue one), not both")
    seed = args.seed
    if args.resume and seed is None:
        seed = resume_seed(Path(args.resume))
    prepared = prepare(load(args.config, seed, args.settings), args.config)
    out = Path(args.resume or args.out or default_out(prepared.config))
    if args.resume:
        state = resume_state(prepared, out)
        if state.stop_reason is not None and (out / "best.json").is_file():  # else: killed while writing results
            print(f"evoplan: {out}: this run is finished (stopped by {state.stop_reason} after "
                  f"{state.evaluations} evaluations, generation {state.algorithm.generation}); "
                  "nothing to resume", file=sys.stderr)
            print(json.dumps(_summary(out, state)))
            return 0
    state = execute(prepared, out, resume=bool(args.resume), progress=False if args.quiet else None)
    print(json.dumps(_summary(out, state)))
    return 0


def _summary(out: Path, state) -> dict:
    return {
        "out": str(out),
        "best": state.best_f,
        "evaluations": state.evaluations,
        "generations": state.algorithm.generation,
        "failures": state.failures,
        "stop_reason": state.stop_reason,
    }
