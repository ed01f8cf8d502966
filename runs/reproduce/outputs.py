"""Where a reproduction script writes: outside the repository unless asked.

By default a script writes its report (and figures) into ``results/reproduce/`` under the
current directory, so running it never rewrites a tracked file. ``--regenerate`` writes the
committed report beside the script instead (the files under ``runs/reproduce/``), and
``--out`` / ``--png`` name any other place.
"""

from __future__ import annotations

import argparse
from pathlib import Path

DEFAULT_DIR = Path("results") / "reproduce"


def add_report_options(ap: argparse.ArgumentParser, figures: dict[str, str] | None = None) -> None:
    """``--out`` (the report), one option per figure (``{"png": "x_best.png"}``), ``--regenerate``."""
    ap.add_argument("--out", default=None, help=f"the report (default: {DEFAULT_DIR}/<script>.md under the "
                                                "current directory; --regenerate: the committed one)")
    for option, name in (figures or {}).items():
        ap.add_argument(f"--{option}", default=None,
                        help=f"figure (default: {DEFAULT_DIR}/{name}; --regenerate: the committed one)")
    ap.add_argument("--regenerate", action="store_true",
                    help="rewrite the committed report and figures beside this script")


def resolve_report_paths(args: argparse.Namespace, script: str, figures: dict[str, str] | None = None) -> None:
    """Fill ``args.out`` and the figure options left unset: the committed files with
    ``--regenerate``, else ``results/reproduce/`` under the current directory."""
    here = Path(script).resolve().parent
    base = here if args.regenerate else DEFAULT_DIR
    if args.out is None:
        args.out = str(base / Path(script).with_suffix(".md").name)
    for option, name in (figures or {}).items():
        if getattr(args, option) is None:
            setattr(args, option, str(base / name))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    for option in figures or {}:
        if getattr(args, option):
            Path(getattr(args, option)).parent.mkdir(parents=True, exist_ok=True)


def write_report(args: argparse.Namespace, text: str) -> None:
    """Write the report to ``args.out`` and print it, then where it went."""
    Path(args.out).write_text(text)
    print(text)
    print(f"wrote {args.out}")
