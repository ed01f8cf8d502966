"""Re-analysis of a study folder: each costly output is rebuilt only when its inputs changed.

Running a finished study again (or resuming one) rewrites its analysis. The cheap tables
(``runs.csv``, ``summary.csv``, ``tests.csv``, the Friedman tables, ``report.md``) are always
rewritten; each figure, ``bayes.csv`` (baycomp's sampling) and the ``ioh/`` export is keyed
by a SHA-256 of what it is made from: the runs' values (every column of ``runs.csv`` but
the wall time), the bytes of their history and trace files, the settings it takes
(reference, alpha, rope, targets) and the source of the modules that compute and draw it, so
a code change rebuilds it too. ``analysis.json`` in the study folder keeps the keys, and
what the last analysis rebuilt and reused.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from .. import __version__
from ..engine import write_atomic

FILE = "analysis.json"
CODE = ("figure_style.py", "study/curves.py", "study/figures.py", "study/ioh_export.py", "study/ioh_ids.py",
        "study/measure.py", "study/ranking.py", "study/statistics.py")


def code_digest() -> str:
    """A digest of evoplan's version and the modules that compute and draw the costly outputs."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(__version__.encode())
    for name in CODE:
        h.update((root / name).read_bytes())
    return h.hexdigest()


def digest(*parts: Any) -> str:
    """SHA-256 of ``parts``: frames and series by their CSV text, arrays by dtype, shape and
    bytes, everything else by its sorted JSON (or repr)."""
    h = hashlib.sha256()
    for part in parts:
        if isinstance(part, (pd.DataFrame, pd.Series)):
            h.update(part.to_csv().encode())
        elif isinstance(part, np.ndarray):
            h.update(f"{part.dtype}{part.shape}".encode() + np.ascontiguousarray(part).tobytes())
        else:
            h.update(json.dumps(part, sort_keys=True, default=repr).encode())
        h.update(b"\x00")
    return h.hexdigest()


class AnalysisMemo:
    """The keys of a study folder's costly outputs (``analysis.json``)."""

    def __init__(self, out: Path) -> None:
        self.out = Path(out)
        self.code = code_digest()
        try:
            self.keys: dict[str, str] = dict(json.loads((self.out / FILE).read_text())["keys"])
        except (OSError, ValueError, KeyError, TypeError):
            self.keys = {}
        self.rebuilt: list[str] = []
        self.reused: list[str] = []

    def key(self, *parts: Any) -> str:
        return digest(self.code, *parts)

    def fresh(self, name: str, key: str) -> bool:
        """Whether ``name`` exists and was made from inputs with this ``key`` (counted as reused);
        else it is counted as rebuilt, under this key."""
        if self.keys.get(name) == key and (self.out / name).exists():
            self.reused.append(name)
            return True
        self.keys[name] = key
        self.rebuilt.append(name)
        return False

    def save(self) -> None:
        doc = {"keys": self.keys, "last": {"rebuilt": self.rebuilt, "reused": self.reused}}
        write_atomic(self.out / FILE, (json.dumps(doc, indent=1, sort_keys=True) + "\n").encode())
