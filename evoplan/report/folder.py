"""A results folder's kind and its files, read as data with one-line errors naming the file."""

from __future__ import annotations

import json
from pathlib import Path

from ..errors import ConfigError

#: the file that makes a folder of each kind (checked in this order)
MARKERS = {"run": "history.csv", "study": "runs.csv", "simulate": "simulation.json", "machine": "summary.json"}


def kind_of(folder: Path) -> str:
    """``"run"``, ``"study"`` or ``"simulate"``; ``ConfigError`` when ``folder`` is none of them."""
    if not folder.is_dir():
        raise ConfigError(f"{folder}: not a folder (give a run, study, simulate or machine results folder)")
    for kind, name in MARKERS.items():
        if (folder / name).is_file():
            return kind
    wanted = ", ".join(MARKERS.values())
    raise ConfigError(f"{folder}: not a results folder (it has none of {wanted})")


def read_csv(path: Path, columns: tuple[str, ...] = ()):
    """``path`` as a pandas DataFrame holding ``columns``; one line naming the file otherwise."""
    import pandas as pd

    try:
        table = pd.read_csv(path)
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise ConfigError(f"{path}: unreadable CSV ({' '.join(str(e).split())})") from None
    missing = [c for c in columns if c not in table.columns]
    if missing:
        raise ConfigError(f"{path}: missing column(s) {', '.join(missing)}")
    if table.empty:
        raise ConfigError(f"{path}: no rows")
    return table


def read_json(path: Path) -> dict:
    """``path`` as a JSON object; one line naming the file otherwise."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise ConfigError(f"{path}: unreadable JSON ({' '.join(str(e).split())})") from None
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: expected a JSON object, got {type(data).__name__}")
    return data
