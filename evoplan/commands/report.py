"""``evoplan report``: one self-contained HTML page of a results folder.

    evoplan report DIR [--out FILE.html]

``DIR`` is a run folder (``history.csv``, ``best.json``, ``config.yaml``; a toolpath run also
``toolpath.apt``), a study folder (``runs.csv``, ``summary.csv``), a simulate folder
(``simulation.json``) or an ``evoplan machine`` folder (``summary.json``). The page opens offline: plotly's JavaScript is inlined, nothing is
fetched. The folder is read as data; its problem is never built. Default output:
``DIR/report.html``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from . import COMMANDS


def port(text: str) -> int:
    """``--port``: an integer 0-65535 (0: any free port), else a one-line usage error."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer port") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"{value} is out of range (1-65535, or 0 for a free port)")
    return value


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("report", help=COMMANDS["report"],
                       description="One self-contained HTML page of a results folder: a run "
                                   "(history.csv), a study (runs.csv), a simulate folder "
                                   "(simulation.json) or an evoplan machine folder (summary.json).")
    p.add_argument("folder", metavar="DIR",
                   help="a run, study, simulate or machine results folder")
    p.add_argument("--out", metavar="FILE.html",
                   help="the HTML file, not a folder (default: DIR/report.html)")
    p.add_argument("--watch", action="store_true",
                   help="serve the report on 127.0.0.1 and refresh it as the folder's data grow")
    p.add_argument("--port", type=port, default=0,
                   help="with --watch: the port, 1-65535 (default 0: a free one)")
    p.add_argument("--timeout", type=float, default=3600.0, metavar="S",
                   help="with --watch: stop after S seconds at most (default 3600)")
    return p


def main(args) -> int:
    from ..errors import ConfigError
    from ..extras import require

    require("plotly", "report", "evoplan report")
    from ..engine import write_atomic
    from ..report import build

    out = Path(args.out) if args.out else Path(args.folder) / "report.html"
    if out.is_dir():
        raise ConfigError(f"{out}: --out is a folder; give the HTML file to write (e.g. {out / 'report.html'})")
    if args.watch:
        import sys

        from ..report.watch import serve

        if not Path(args.folder).is_dir():
            raise ConfigError(f"{args.folder}: not a folder")
        if not (args.timeout > 0):
            raise ConfigError(f"--timeout {args.timeout}: must be a positive number of seconds")
        if not out.parent.is_dir():
            raise ConfigError(f"{out}: --out: folder {out.parent} does not exist")
        reason = serve(Path(args.folder), args.port, args.timeout, out=out,
                       announce=lambda m: print(m, file=sys.stderr, flush=True))
        print(out)
        print(f"evoplan: watch stopped ({reason})", file=sys.stderr)
        return 0
    text = build(args.folder)
    if not out.parent.is_dir():
        raise ConfigError(f"{out}: --out: folder {out.parent} does not exist")
    write_atomic(out, text.encode("utf-8"))
    print(out)
    return 0
