"""Surfaces from plain data (as they come from a YAML ``params:`` mapping), validated once.

Accepted forms of ``surface``:

- ``"fountas"`` / ``{"type": "fountas"}``: Fountas et al. Eq. 14.
- ``"choi"`` / ``{"type": "choi"}``: Choi's bicubic Bezier surface (Djebali Table 3).
- ``{"type": "bezier", "poles": NET, "degree": [p, q]}``: NET of shape (p+1, q+1, 3);
  ``degree`` is optional (then any (p+1, q+1, 3) net with p, q >= 1 is accepted).
- ``{"type": "bspline", "poles": NET, "degree": [p, q] (default [3, 3]),
  "knots_u": [...], "knots_v": [...]}``: knots optional (clamped uniform).
- ``{"type": "nurbs", "poles": NET, "weights": WEIGHTS, ...}``: the ``bspline`` keys plus
  ``weights`` (nu, nv), every weight finite and > 0 (rational B-spline, ``nurbs.py``).

Optional for every type: ``flip_normal: true`` (the tool side is opposite to the default,
which is the side with +z at the domain centre).

NET is a nested list ``poles[i][j] = [x, y, z]`` (i along u, j along v), or the path of a
file holding it (relative paths are taken from ``base_dir``, the config file's folder):

- ``.json`` / ``.yaml`` / ``.yml``: the nested list, or a mapping with a ``poles`` key;
- ``.csv``: one pole per row ``i,j,x,y,z`` (an optional header row is skipped), every
  (i, j) of the grid exactly once.

WEIGHTS takes the same forms: a nested list ``weights[i][j] = w``, or a file (a mapping with
a ``weights`` key in JSON / YAML, rows ``i,j,w`` in CSV).

Each type has one builder in ``BUILDERS`` (type -> function(spec, key, base_dir) -> Surface).

Errors are ``ValueError`` with one line starting with the key path, e.g.
``surface.poles: expected shape (4, 4, 3), got (3, 4, 3)``.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from .bezier import BezierSurface, choi_surface
from .bspline import BSplineSurface
from .nurbs import NURBSSurface
from .surface import Surface, fountas_surface
from .surface_checks import check_height_field

__all__ = ["parse_surface", "load_poles"]

_KEYS = {
    "fountas": {"type", "flip_normal"},
    "choi": {"type", "flip_normal"},
    "bezier": {"type", "poles", "degree", "flip_normal"},
    "bspline": {"type", "poles", "degree", "knots_u", "knots_v", "flip_normal"},
    "nurbs": {"type", "poles", "weights", "degree", "knots_u", "knots_v", "flip_normal"},
}


def _fail(key: str, msg: str):
    raise ValueError(f"{key}: {msg}")


MAX_NET_BYTES = 4 * 2**20


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


def load_poles(source, key: str = "surface.poles", base_dir=None,
               field: str = "poles") -> np.ndarray:
    """A control net (nu, nv, 3) float from a nested list or a file path (see module doc);
    ``field="weights"`` reads a weights net (nu, nv) the same way (CSV rows ``i,j,w``)."""
    if isinstance(source, (str, Path)):
        path = Path(source)
        if not path.is_absolute() and base_dir is not None:
            path = Path(base_dir) / path
        if not path.is_file():
            _fail(key, f"file not found: {path}")
        suffix = path.suffix.lower()
        import yaml

        if path.stat().st_size > MAX_NET_BYTES:
            _fail(key, f"{path} is larger than {MAX_NET_BYTES // 2**20} MiB: not a control net")
        try:
            if suffix == ".json":
                data = json.loads(path.read_text(encoding="utf-8"))
            elif suffix in (".yaml", ".yml"):
                data = yaml.load(path.read_text(encoding="utf-8"), Loader=_net_loader())
            elif suffix == ".csv":
                return _poles_from_csv(path, key, 3 if field == "poles" else 1)
            else:
                _fail(key, f"unsupported file type {suffix!r} (use .json, .yaml or .csv)")
        except (OSError, ValueError, RecursionError, yaml.YAMLError) as exc:
            if str(exc).startswith(key):
                raise
            _fail(key, f"cannot read {path}: {str(exc).splitlines()[0]}")
        if isinstance(data, dict):
            if field not in data:
                _fail(key, f"{path} has no {field!r} key")
            data = data[field]
        source = data
    try:
        net = np.array(source, dtype=float)
    except (TypeError, ValueError):
        _fail(key, "expected a nested list poles[i][j] = [x, y, z] of numbers" if field == "poles"
              else f"expected a nested list {field}[i][j] of numbers")
    return net


def _poles_from_csv(path: Path, key: str, width: int = 3) -> np.ndarray:
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
                _fail(key, f"{path} line {n + 1}: expected numbers {cols}")  # the line is not echoed
            if len(vals) != 2 + width:
                _fail(key, f"{path} line {n + 1}: expected {2 + width} columns {cols}, "
                      f"got {len(vals)}")
            rows.append(vals)
    if not rows:
        _fail(key, f"{path} holds no poles")
    a = np.array(rows)
    ij = a[:, :2]
    if np.any(ij != np.round(ij)) or np.any(ij < 0):
        _fail(key, f"{path}: i, j must be non-negative integers")
    nu, nv = int(ij[:, 0].max()) + 1, int(ij[:, 1].max()) + 1
    net = np.full((nu, nv, width), np.nan)
    seen = np.zeros((nu, nv), int)
    for i, j, *xyz in rows:
        net[int(i), int(j)] = xyz
        seen[int(i), int(j)] += 1
    if np.any(seen != 1):
        i, j = np.argwhere(seen != 1)[0]
        _fail(key, f"{path}: pole ({i}, {j}) given {seen[i, j]} times (expected once)")
    return net if width == 3 else net[..., 0]


def _check_net(net: np.ndarray, key: str, expected=None) -> None:
    if expected is not None and net.shape != expected:
        _fail(key, f"expected shape {expected}, got {net.shape}")
    if net.ndim != 3 or net.shape[2] != 3 or net.shape[0] < 2 or net.shape[1] < 2:
        _fail(key, f"expected shape (nu, nv, 3) with nu, nv >= 2, got {net.shape}")
    bad = ~np.isfinite(net)
    if bad.any():
        i, j, c = np.argwhere(bad)[0]
        _fail(key, f"contains NaN or infinite values (first at [{i}][{j}][{c}])")


def _degree(value, key: str) -> tuple[int, int]:
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        value = [value, value]
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or not all(isinstance(x, (int, np.integer)) and not isinstance(x, bool) and x >= 1
                       for x in value)):
        _fail(key, f"expected two integers >= 1 [p, q], got {value!r}")
    return int(value[0]), int(value[1])


def _knots(value, n_poles: int, degree: int, key: str):
    if value is None:
        return None
    try:
        t = np.array(value, dtype=float)
    except (TypeError, ValueError):
        _fail(key, "expected a list of numbers")
    if t.ndim != 1 or len(t) != n_poles + degree + 1:
        _fail(key, f"expected {n_poles + degree + 1} knots (poles + degree + 1), got {t.size}")
    if not np.all(np.isfinite(t)) or np.any(np.diff(t) < 0):
        _fail(key, "knots must be finite and non-decreasing")
    if not t[-degree - 1] > t[degree]:
        _fail(key, "the knot vector spans an empty parameter interval")
    return t


def _checked(surf: Surface, key: str) -> Surface:
    check_height_field(surf, key)  # no fold, overhang, vertical wall or self-overlap
    return surf


def _net(spec, key: str, base_dir) -> np.ndarray:
    if "poles" not in spec:
        _fail(f"{key}.poles", "missing")
    return load_poles(spec["poles"], f"{key}.poles", base_dir)


def _bezier(spec, key: str, base_dir) -> Surface:
    net = _net(spec, key, base_dir)
    expected = None
    if "degree" in spec:
        p, q = _degree(spec["degree"], f"{key}.degree")
        expected = (p + 1, q + 1, 3)
    _check_net(net, f"{key}.poles", expected)
    return _checked(BezierSurface(net), key)


def _bspline_args(spec, key: str, base_dir):
    net = _net(spec, key, base_dir)
    p, q = _degree(spec.get("degree", [3, 3]), f"{key}.degree")
    _check_net(net, f"{key}.poles")
    if net.shape[0] <= p or net.shape[1] <= q:
        _fail(f"{key}.poles", f"a degree ({p}, {q}) B-spline needs at least "
              f"({p + 1}, {q + 1}, 3) poles, got {net.shape}")
    tu = _knots(spec.get("knots_u"), net.shape[0], p, f"{key}.knots_u")
    tv = _knots(spec.get("knots_v"), net.shape[1], q, f"{key}.knots_v")
    return net, (p, q), tu, tv


def _bspline(spec, key: str, base_dir) -> Surface:
    return _checked(BSplineSurface(*_bspline_args(spec, key, base_dir)), key)


def _weights(spec, key: str, base_dir, shape) -> np.ndarray:
    wkey = f"{key}.weights"
    if "weights" not in spec:
        _fail(wkey, "missing (a nurbs surface needs one weight per pole)")
    w = load_poles(spec["weights"], wkey, base_dir, field="weights")
    if w.shape != shape:
        _fail(wkey, f"expected shape {shape} (one weight per pole), got {w.shape}")
    bad = ~np.isfinite(w)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        _fail(wkey, f"contains NaN or infinite values (first at [{i}][{j}])")
    if np.any(w <= 0):
        i, j = np.argwhere(w <= 0)[0]
        _fail(wkey, f"weights must be > 0, got {w[i, j]:g} at [{i}][{j}]")
    return w


def _nurbs(spec, key: str, base_dir) -> Surface:
    net, degree, tu, tv = _bspline_args(spec, key, base_dir)
    w = _weights(spec, key, base_dir, net.shape[:2])
    return _checked(NURBSSurface(net, w, degree, tu, tv), key)


BUILDERS = {
    "fountas": lambda spec, key, base_dir: fountas_surface(),
    "choi": lambda spec, key, base_dir: choi_surface(),
    "bezier": _bezier,
    "bspline": _bspline,
    "nurbs": _nurbs,
}


def parse_surface(spec, key: str = "surface", base_dir=None) -> Surface:
    """Build a surface from plain data (see the module docstring)."""
    if isinstance(spec, Surface):
        return spec
    if isinstance(spec, str):
        spec = {"type": spec}
    if not isinstance(spec, dict):
        _fail(key, f"expected a name or a mapping, got {spec!r}")
    kind = spec.get("type")
    if not isinstance(kind, str) or kind not in _KEYS:
        _fail(f"{key}.type", f"expected one of {', '.join(_KEYS)}, got {kind!r}")
    unknown = set(spec) - _KEYS[kind]
    if unknown:
        _fail(key, f"unknown key(s) for a {kind} surface: {', '.join(sorted(unknown))}")
    flip = spec.get("flip_normal", False)
    if not isinstance(flip, bool):
        _fail(f"{key}.flip_normal", f"expected true or false, got {flip!r}")
    surf = BUILDERS[kind](spec, key, base_dir)
    if flip:
        surf.normal_sign = -surf.normal_sign
    return surf
