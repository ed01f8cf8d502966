"""``evoplan report``: one self-contained HTML page of a results folder.

    evoplan report DIR [--out FILE.html]

``DIR`` is a run folder (``history.csv``, ``best.json``, ``config.yaml``; a toolpath run also
``toolpath.apt``), a study folder (``runs.csv``, ``summary.csv``) or a simulate folder
(``simulation.json``). The page opens offline: plotly's JavaScript is inlined, nothing is
fetched. The folder is read as data; its problem is never built. Default output:
``DIR/report.html``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from . import COMMANDS


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("report", help=COMMANDS["report"])
    p.add_argument("folder", metavar="DIR", help="a run, study or simulate results folder")
    p.add_argument("--out", metavar="FILE.html", help="the HTML file (default: DIR/report.html)")
    p.add_argument("--watch", action="store_true",
                   help="serve the report on 127.0.0.1 and refresh it as history.csv grows")
    p.add_argument("--port", type=int, default=0, help="with --watch: the port (default: a free one)")
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
    if args.watch:
        import sys

        from ..report.watch import serve

        if not Path(args.folder).is_dir():
            raise ConfigError(f"{args.folder}: not a folder")
        if not (args.timeout > 0):
            raise ConfigError(f"--timeout {args.timeout}: must be a positive number of seconds")
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
