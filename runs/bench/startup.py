"""Start-up time of ``evoplan [COMMAND] --help``, each in a fresh interpreter, interleaved.

Beside them, two baselines of the same run: the interpreter alone (``python -c pass``, the
floor), and an eager start: a fresh interpreter that imports every sub-command module with
what their parsers used to import (the zoning and machining file models, the backends) and
prints the help.

    python runs/bench/startup.py [--repeat 5]

Not a test: it prints measured medians (wall seconds; say whether the host was shared).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

from evoplan.commands import COMMANDS

EAGER = ("import importlib, sys; from evoplan.commands import COMMANDS; "
         "[importlib.import_module('evoplan.commands.' + c) for c in COMMANDS]; "
         "import evoplan.commands.zone_config, evoplan.commands.machine_config, evoplan.parallel; "
         "from evoplan.cli import main; sys.argv = ['evoplan', '--help']; main()")


def seconds(argv: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(argv, capture_output=True, timeout=120)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    runs = {"evoplan --help": [sys.executable, "-m", "evoplan", "--help"]}
    runs |= {f"evoplan {c} --help": [sys.executable, "-m", "evoplan", c, "--help"] for c in COMMANDS}
    runs["eager baseline: every command imported, --help"] = [sys.executable, "-c", EAGER]
    runs["floor: the interpreter alone (python -c pass)"] = [sys.executable, "-c", "pass"]
    times: dict[str, list[float]] = {k: [] for k in runs}
    for _ in range(args.repeat):
        for name, argv in runs.items():
            times[name].append(seconds(argv))
    for name, t in times.items():
        print(f"{name:52s} median {statistics.median(t):.3f} s  (range {min(t):.3f}-{max(t):.3f})")


if __name__ == "__main__":
    main()
