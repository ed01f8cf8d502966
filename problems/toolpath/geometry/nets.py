"""Control nets from plain data: nested lists or files (``.json``, ``.yaml``, ``.csv``), checked.

NET is a nested list ``poles[i][j] = [x, y, z]`` (i along u, j along v), or the path of a
file holding it (relative paths are taken from ``base_dir``, the config file's folder):

- ``.json`` / ``.yaml`` / ``.yml``: the nested list, or a mapping with a ``poles`` key
  (``weights`` for a NURBS weight net);
- ``.csv``: one pole per row ``i,j,x,y,z`` (a weight net: ``i,j,w``; an optional header row
  is skipped), every (i, j) of the grid exactly once.

Errors are ``ValueError`` with one line starting with the key path, e.g.
``surface.poles: expected shape (4, 4, 3), got (3, 4, 3)``.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

__all__ = ["MAX_NET_BYTES", "load_poles", "load_net", "check_net", "parse_degree", "check_knots",
           "fail"]

MAX_NET_BYTES = 4 * 2**20


def fail(key: str, msg: str):
    raise ValueError(f"{key}: {msg}")


def _shown(path) -> str:
    """A path as a message shows it: as written, or quoted with its escapes when it holds a
    character that is not printable (a newline would break the message's one line)."""
    text = str(path)
    return text if text.isprintable() else repr(text)


def _net_loader():
    """PyYAML's safe loader without aliases: a control net never needs them, and an alias
    bomb expands to gigabytes. Deep nesting ends in a RecursionError, which is caught."""
    import yaml

    class NetLoader(yaml.SafeLoader):
        def compose_node(self, parent, index):
            if self.check_event(yaml.events.AliasEvent):
                raise yaml.YAMLError("aliases are not allowed in a control-net file")
            return super().compose_node(parent, index)

    return NetLoader


def resolve(source, key: str, base_dir=None) -> Path:
    """The file ``source`` (relative to ``base_dir``), or one line: file not found."""
    path = Path(source)
    if not path.is_absolute() and base_dir is not None:
        path = Path(base_dir) / path
    if not path.is_file():
        fail(key, f"file not found: {_shown(path)}")
    return path


def load_net(source, key: str, base_dir=None, field: str = "poles", width: int = 3) -> np.ndarray:
    """A net of ``width`` values per (i, j) (poles: 3, weights: 1) from a list or a file."""
    if isinstance(source, (str, Path)):
        path = resolve(source, key, base_dir)
        suffix = path.suffix.lower()
        import yaml

        if path.stat().st_size > MAX_NET_BYTES:
            fail(key, f"{_shown(path)} is larger than {MAX_NET_BYTES // 2**20} MiB: not a control net")
        try:
            if suffix == ".json":
                data = json.loads(path.read_text(encoding="utf-8"))
            elif suffix in (".yaml", ".yml"):
                data = yaml.load(path.read_text(encoding="utf-8"), Loader=_net_loader())
            elif suffix == ".csv":
                return _net_from_csv(path, key, width)
            else:
                fail(key, f"unsupported file type {suffix!r} (use .json, .yaml or .csv)")
        except (OSError, ValueError, RecursionError, yaml.YAMLError) as exc:
            if str(exc).startswith(key):
                raise
            fail(key, f"cannot read {_shown(path)}: {str(exc).splitlines()[0]}")
        if isinstance(data, dict):
            if field not in data:
                fail(key, f"{_shown(path)} has no {field!r} key")
            data = data[field]
        source = data
    try:
        net = np.array(source, dtype=float)
    except (TypeError, ValueError):
        what = "poles[i][j] = [x, y, z]" if width == 3 else f"{field}[i][j]"
        fail(key, f"expected a nested list {what} of numbers")
    return net


def load_poles(source, key: str = "surface.poles", base_dir=None) -> np.ndarray:
    """A control net (nu, nv, 3) float from a nested list or a file path (see module doc)."""
    return load_net(source, key, base_dir)


def _net_from_csv(path: Path, key: str, width: int) -> np.ndarray:
    cols = "i,j,x,y,z" if width == 3 else "i,j,w"
    rows = []
    with path.open(newline="") as fh:
        for n, row in enumerate(csv.reader(fh)):
            if not row or all(not c.strip() for c in row):
                continue
            try:
                vals = [float(c) for c in row]
            except ValueError:
                if n == 0:
                    continue  # header
                fail(key, f"{_shown(path)} line {n + 1}: expected numbers {cols}")  # the line is not echoed
            if len(vals) != width + 2:
                fail(key, f"{_shown(path)} line {n + 1}: expected {width + 2} columns {cols}, got {len(vals)}")
            rows.append(vals)
    if not rows:
        fail(key, f"{_shown(path)} holds no poles")
    a = np.array(rows)
    ij = a[:, :2]
    if np.any(ij != np.round(ij)) or np.any(ij < 0):
        fail(key, f"{_shown(path)}: i, j must be non-negative integers")
    nu, nv = int(ij[:, 0].max()) + 1, int(ij[:, 1].max()) + 1
    net = np.full((nu, nv, width), np.nan)
    seen = np.zeros((nu, nv), int)
    for r in a:
        i, j = int(r[0]), int(r[1])
        net[i, j] = r[2:]
        seen[i, j] += 1
    if np.any(seen != 1):
        i, j = np.argwhere(seen != 1)[0]
        fail(key, f"{_shown(path)}: pole ({i}, {j}) given {seen[i, j]} times (expected once)")
    return net if width > 1 else net[..., 0]


def check_net(net: np.ndarray, key: str, expected=None) -> None:
    """A (nu, nv, 3) finite net with nu, nv >= 2 (of shape ``expected`` when given)."""
    if expected is not None and net.shape != expected:
        fail(key, f"expected shape {expected}, got {net.shape}")
    if net.ndim != 3 or net.shape[2] != 3 or net.shape[0] < 2 or net.shape[1] < 2:
        fail(key, f"expected shape (nu, nv, 3) with nu, nv >= 2, got {net.shape}")
    bad = ~np.isfinite(net)
    if bad.any():
        i, j, c = np.argwhere(bad)[0]
        fail(key, f"contains NaN or infinite values (first at [{i}][{j}][{c}])")


def parse_degree(value, key: str) -> tuple[int, int]:
    """(p, q) from an integer or a pair of integers >= 1."""
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        value = [value, value]
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or not all(isinstance(x, (int, np.integer)) and not isinstance(x, bool) and x >= 1
                       for x in value)):
        fail(key, f"expected two integers >= 1 [p, q], got {value!r}")
    return int(value[0]), int(value[1])


def check_knots(value, n_poles: int, degree: int, key: str):
    """A knot vector of n_poles + degree + 1 finite non-decreasing values, or None."""
    if value is None:
        return None
    try:
        t = np.array(value, dtype=float)
    except (TypeError, ValueError):
        fail(key, "expected a list of numbers")
    if t.ndim != 1 or len(t) != n_poles + degree + 1:
        fail(key, f"expected {n_poles + degree + 1} knots (poles + degree + 1), got {t.size}")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) < 0):
        fail(key, "knots must be finite and non-decreasing")
    if not t[-degree - 1] > t[degree]:
        fail(key, "the knot vector spans an empty parameter interval")
    return t
