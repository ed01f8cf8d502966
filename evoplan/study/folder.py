"""The results folder of a study, and resuming it.

Layout::

    DIR/study.yaml               the study, every setting resolved (written first)
    DIR/cells/<key>.json         one finished run: its record and the settings that made it
    DIR/histories/<key>.csv      that run's history (one row per generation, as history.csv)
    DIR/traces/<key>.csv         its improvements: evaluation, best (every new best, as it happened)
    DIR/runs.csv  summary.csv  tests.csv  report.md  figures/*.png   (analysis, rebuilt each time)

A cell's files are written atomically, the history before the record, so a study killed at any
instant leaves only complete cells. Running the same study into the same folder again runs only
the cells without a successful record made by the same settings (missing, failed, or whose
settings changed); the others are read back.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Iterable

import pandas as pd
import yaml

from ..engine import HISTORY_COLUMNS, write_atomic
from ..errors import ConfigError
from .grid import Cell

STUDY_FILE = "study.yaml"
TRACE_COLUMNS = ("evaluation", "best")


class StudyFolder:
    def __init__(self, out: str | Path, name: str) -> None:
        self.out = Path(out)
        self.name = name
        self.cells = self.out / "cells"
        self.histories = self.out / "histories"
        self.traces = self.out / "traces"

    def check(self) -> None:
        """Refuse a folder that holds something other than this study (before any run)."""
        if not self.out.exists():
            return
        if not self.out.is_dir():
            raise ConfigError(f"{self.out}: exists and is not a folder")
        marker = self.out / STUDY_FILE
        if marker.is_file():
            try:
                previous = yaml.safe_load(marker.read_text()) or {}
            except yaml.YAMLError:
                previous = {}
            if previous.get("name") != self.name:
                raise ConfigError(f"{self.out}: holds the study {previous.get('name')!r}, not {self.name!r}: "
                                  "choose another --out")
        elif any(self.out.iterdir()):
            raise ConfigError(f"{self.out}: already exists, is not empty and holds no study: choose another --out")

    def start(self, resolved: dict[str, Any]) -> None:
        self.check()
        self.cells.mkdir(parents=True, exist_ok=True)
        self.histories.mkdir(parents=True, exist_ok=True)
        self.traces.mkdir(parents=True, exist_ok=True)
        write_atomic(self.out / STUDY_FILE, yaml.safe_dump(resolved, sort_keys=False).encode())

    def _record_path(self, cell: Cell) -> Path:
        return self.cells / f"{cell.key}.json"

    def load(self, cell: Cell) -> dict[str, Any] | None:
        """The stored record of ``cell`` if it succeeded with the same settings, else None."""
        try:
            stored = json.loads(self._record_path(cell).read_text())
        except (OSError, ValueError):
            return None
        if stored.get("fingerprint") != cell.fingerprint or stored.get("record", {}).get("status") != "ok":
            return None
        return stored["record"]

    def save(self, cell: Cell, record: dict[str, Any], history: list[tuple],
             trace: list[tuple[int, float]] = ()) -> None:
        extra = len(history[0]) - len(HISTORY_COLUMNS) if history else 0
        frame = pd.DataFrame(history, columns=list(HISTORY_COLUMNS) + list(HISTORY_EXTRA[:extra]))
        write_atomic(self.histories / f"{cell.key}.csv", frame.to_csv(index=False).encode())
        steps = pd.DataFrame(list(trace), columns=list(TRACE_COLUMNS))
        write_atomic(self.traces / f"{cell.key}.csv", steps.to_csv(index=False).encode())
        doc = {"record": record, "fingerprint": cell.fingerprint, "run": cell.run}
        write_atomic(self._record_path(cell), (json.dumps(doc, indent=1) + "\n").encode())

    def history(self, key: str) -> pd.DataFrame:
        path = self.histories / f"{key}.csv"
        if not path.is_file():
            return pd.DataFrame(columns=list(HISTORY_COLUMNS))
        return pd.read_csv(path)

    def trace(self, key: str) -> pd.DataFrame | None:
        """The improvement trace of a run; None for a run saved before traces were kept."""
        path = self.traces / f"{key}.csv"
        return pd.read_csv(path) if path.is_file() else None

    def write_table(self, name: str, frame: pd.DataFrame) -> None:
        write_atomic(self.out / name, frame.to_csv(index=False).encode())

    def write_text(self, name: str, text: str) -> None:
        write_atomic(self.out / name, text.encode())

    def write_bytes(self, name: str, data: bytes) -> None:
        path = self.out / name
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomic(path, data)


HISTORY_EXTRA = ("hypervolume",)  # a history's columns beyond the engine's, when a run has them


RUN_COLUMNS = ["key", "algorithm", "problem", "dimension", "factor", "level", "repetition", "seed", "status",
               "final_best", "best_overall", "optimum", "budget", "evaluations", "cache_hits", "generations", "failures",
               "stop_reason", "wall_seconds", "error", "failure_messages", "best_variables",
               "hypervolume"]  # a multi-objective run's final hypervolume (empty otherwise)


def runs_frame(records: Iterable[dict[str, Any]]) -> pd.DataFrame:
    """``runs.csv``: one row per run, in grid order, the columns of :data:`RUN_COLUMNS`."""
    frame = pd.DataFrame(list(records))
    for col in RUN_COLUMNS:
        if col not in frame:
            frame[col] = None
    return frame[RUN_COLUMNS]
