"""Reading a finished run's results folder as data only.

A results folder is input from anywhere: a colleague's archive, a download, a folder someone
else can write to. Its ``config.yaml`` may name user code (``problem.name: pkg.module:Class``),
and building that problem would import the module, running whatever it holds. So every command
that reads a results folder (``simulate --run``, ``machine --from-run``) rebuilds the problem
from data only: a problem registered with evoplan (``kubota``, ``toolpath``, ...) or a pymoo test
problem. A folder whose run used user code is refused with one line, unless the user names that
module on the command line (``--trust-code MODULE``): then the user, not the folder, decided to
run it. ``run --resume`` is as strict by construction: it builds the problem from the run file
given on the command line and only compares the folder's fingerprint.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .config import read_yaml
from .errors import ConfigError
from .problem_factory import code_module
from .safe_yaml import short


_DOTTED = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*")


@dataclass(frozen=True)
class RunFolder:
    """The settings and best solution of a finished run, read as data."""

    path: Path
    config: dict[str, Any]
    best: dict[str, Any]

    @property
    def config_path(self) -> Path:
        return self.path / "config.yaml"

    @property
    def problem(self) -> dict[str, Any]:
        problem = self.config.get("problem", {})
        return problem if isinstance(problem, dict) else {}


def read_run_folder(path: str | Path, trust_code: str | None = None, option: str = "--run",
                    can_trust: bool = True) -> RunFolder:
    """``config.yaml`` and ``best.json`` of the finished run in ``path``; one-line ``ConfigError``.

    The folder's problem must be data (a registered name or a pymoo test problem); a
    ``module:Class`` problem is refused unless ``trust_code`` names exactly its module.
    Nothing is imported here. ``can_trust``: the command offers ``--trust-code`` (the error
    names it); a command that cannot run user problems at all says so instead.
    """
    run = Path(path)
    for name in ("config.yaml", "best.json"):
        if not (run / name).is_file():
            raise ConfigError(f"{run}: {option}: no {name}: not a finished run's results folder")
    config = read_yaml(run / "config.yaml")
    try:
        best = json.loads((run / "best.json").read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise ConfigError(f"{run / 'best.json'}: unreadable ({e})") from None
    if not isinstance(best, dict):
        raise ConfigError(f"{run / 'best.json'}: expected a JSON object")
    folder = RunFolder(run, config, best)
    name = folder.problem.get("name")
    if not isinstance(name, str):
        raise ConfigError(f"{folder.config_path}: problem.name: missing or not a string")
    module = code_module(name)
    if module is not None and module != trust_code:
        shown = module if _DOTTED.fullmatch(module) else short(module)
        hint = (f"if you trust module {shown}, pass --trust-code {shown}" if can_trust
                else f"{option} takes only runs of evoplan's own problems")
        raise ConfigError(f"{folder.config_path}: problem.name: {short(name)} is user code, and a "
                          f"results folder runs no code: {hint}")
    return folder
