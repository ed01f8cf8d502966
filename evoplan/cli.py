"""The ``evoplan`` command line; each sub-command lives in ``evoplan/commands/<name>.py``.

User errors (bad YAML, unknown names, bad values, missing files) print one line
``evoplan: error: ...`` and exit with code 2, leaving no results folder behind.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading

from . import __version__
from .commands import COMMANDS
from .errors import EvoplanError


class OneLineParser(argparse.ArgumentParser):
    """argparse with its usage errors on one line (``evoplan: error: ...``, exit 2); ``-h`` shows usage."""

    command_hint: str | None = None  # the command being parsed, for errors the top level reports

    def error(self, message: str):
        command = self.prog.removeprefix("evoplan").strip() or self.command_hint
        hint = f" (evoplan {command} -h for usage)" if command else " (evoplan -h for usage)"
        self.exit(2, f"evoplan: error: {' '.join(message.split())}{hint}\n")


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The parser, with the full options of the one command ``argv`` names.

    Every command is listed (``COMMANDS``: name and one-line help), but only the module of the
    command being run is imported, so ``evoplan --help`` and ``evoplan run --help`` load neither
    the toolpath engine nor numba. ``argv=None`` builds every command (for documentation).
    """
    parser = OneLineParser(prog="evoplan", description="Evolutionary toolpath optimization.")
    parser.add_argument("--version", action="version", version=f"evoplan {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    chosen = None if argv is None else _command(argv)
    if chosen in COMMANDS:  # unrecognized options are reported by the top level: name the command
        parser.command_hint = chosen
    for name, text in COMMANDS.items():
        if argv is None or name == chosen:
            module = importlib.import_module(f"evoplan.commands.{name}")
            module.add_parser(sub).set_defaults(func=module.main)
        else:
            sub.add_parser(name, help=text)
    return parser


def _command(argv: list[str]) -> str | None:
    """The command named in ``argv``: its first word that is not an option."""
    return next((w for w in argv if not w.startswith("-")), None)


def _terminate(signum, frame):
    """SIGTERM ends evoplan like Ctrl-C: pools close (workers killed), the last checkpoint stays."""
    raise KeyboardInterrupt


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    args = build_parser(argv).parse_args(argv)
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        code = args.func(args)
        sys.stdout.flush()  # a broken pipe shows here, not in Python's own flush at exit
        return code
    except EvoplanError as e:
        print(f"evoplan: error: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader went away (``evoplan ... | head``): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error when Python flushes stdout at exit
        return 141  # 128 + SIGPIPE, as a shell tool killed by the broken pipe
    except KeyboardInterrupt:
        print("evoplan: interrupted (resume a run with --resume DIR, a study by running it again)", file=sys.stderr)
        return 130
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
