"""Data-only checkpoints: a run's state as JSON and numpy arrays in one ``.npz``, never a pickle.

A results folder may come from anywhere, so ``--resume`` must not run code from it. The
checkpoint is an ``.npz`` (a zip of ``.npy`` arrays, read with ``allow_pickle=False``) holding:

- ``__state__``: UTF-8 JSON of the state's plain values (numbers, strings, lists; ``Infinity``
  and ``NaN`` as Python's ``json`` writes them), with arrays referenced by name;
- one entry per numpy array (numeric or boolean dtypes only);
- ``__sha256__``: SHA-256 over the JSON and every array (name, dtype, shape, bytes), so a
  flipped bit is refused instead of resuming with different numbers.

What is stored: the :class:`~evoplan.engine.RunState` and the algorithm, attribute by attribute
(:meth:`Algorithm.state_dict`); a random generator as its ``bit_generator.state`` (a dict of
integers); the evaluation cache through its ``to_data``/``from_data``; a setting model
(pydantic) not at all: it is rebuilt from the run file, whose fingerprint must match.
Resuming builds a fresh state from the run file and loads the stored values into it
(:func:`load_into`), so no class is ever named by the file.

Algorithm state that is not data is refused by name: the pymoo adapters keep pymoo's algorithm
object (its populations, operators and its own ``random`` state live in arbitrary Python
objects) and the DEAP adapter keeps DEAP individuals and a toolbox of functions. Their runs
write a checkpoint that says so, and ``--resume`` refuses them with one line.
"""

from __future__ import annotations

import base64
import dataclasses
import hashlib
import io
import json
import zipfile
from typing import Any

import numpy as np
from pydantic import BaseModel

from . import __version__
from .algorithms.base import Algorithm

FORMAT = "evoplan-checkpoint/1"
BIT_GENERATORS = {"PCG64", "PCG64DXSM", "MT19937", "Philox", "SFC64"}
ARRAY_KINDS = set("biufc")  # bool, int, uint, float, complex: no objects, no strings


class NotData(TypeError):
    """A value of the state that cannot be written as plain data (the message names it)."""


class CheckpointError(ValueError):
    """A checkpoint that cannot be resumed: corrupt, foreign, or of another configuration."""


class _Encoder:
    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}

    def __call__(self, value: Any, where: str) -> Any:
        if value is None or isinstance(value, (bool, int, float, str)):
            return value
        if isinstance(value, np.generic):
            return self(value.item(), where)
        if isinstance(value, np.ndarray):
            if value.dtype.kind not in ARRAY_KINDS:
                raise NotData(f"{where}: an array of {value.dtype} (not numbers)")
            name = f"a{len(self.arrays)}"
            self.arrays[name] = np.ascontiguousarray(value)
            return {"$array": name}
        if isinstance(value, np.random.Generator):
            return {"$rng": value.bit_generator.state}
        if isinstance(value, tuple):
            return {"$tuple": [self(v, f"{where}[{i}]") for i, v in enumerate(value)]}
        if isinstance(value, list):
            return [self(v, f"{where}[{i}]") for i, v in enumerate(value)]
        if isinstance(value, dict):
            return {"$dict": [[self(k, f"{where} key"), self(v, f"{where}.{k}" if isinstance(k, str) else f"{where}[{k!r}]")]
                              for k, v in value.items()]}
        if isinstance(value, bytes):
            return {"$bytes": base64.b64encode(value).decode()}
        if isinstance(value, BaseModel):
            return {"$config": type(value).__name__}
        if hasattr(value, "to_data") and hasattr(type(value), "from_data"):
            return {"$data": type(value).__name__, "value": self(value.to_data(), where)}
        if isinstance(value, Algorithm):
            return {"$object": type(value).__name__, "attrs": self(value.state_dict(), where)}
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            attrs = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
            return {"$object": type(value).__name__, "attrs": self(attrs, where)}
        raise NotData(f"{where}: a {type(value).__module__}.{type(value).__qualname__} object")


def _decode(value: Any, arrays, current: Any, where: str) -> Any:
    """``value`` as Python data; objects and generators are loaded *into* ``current``."""
    if not isinstance(value, dict):
        return [_decode(v, arrays, None, where) for v in value] if isinstance(value, list) else value
    if "$array" in value:
        return arrays[value["$array"]]
    if "$tuple" in value:
        return tuple(_decode(v, arrays, None, where) for v in value["$tuple"])
    if "$dict" in value:
        return {_freeze(_decode(k, arrays, None, where)): _decode(v, arrays, None, where) for k, v in value["$dict"]}
    if "$bytes" in value:
        return base64.b64decode(value["$bytes"])
    if "$rng" in value:
        state = value["$rng"]
        name = state.get("bit_generator") if isinstance(state, dict) else None
        if name not in BIT_GENERATORS:
            raise CheckpointError(f"{where}: unknown bit generator {str(name)[:40]!r}")
        rng = current if isinstance(current, np.random.Generator) else np.random.Generator(getattr(np.random, name)())
        rng.bit_generator.state = state
        return rng
    if "$config" in value:
        _same_class(current, value["$config"], where)
        return current  # rebuilt from the run file (same fingerprint)
    if "$data" in value:
        _same_class(current, value["$data"], where)
        return type(current).from_data(_decode(value["value"], arrays, None, where))
    if "$object" in value:
        _same_class(current, value["$object"], where)
        values = {k: _decode(raw, arrays, getattr(current, k, None), f"{where}.{k}") for k, raw in value["attrs"]["$dict"]}
        if isinstance(current, Algorithm):
            current.load_state_dict(values)
        else:
            for k, v in values.items():
                setattr(current, k, v)
        return current
    raise CheckpointError(f"{where}: unexpected entry {sorted(value)[:3]}")


def _freeze(key):
    return tuple(key) if isinstance(key, list) else key


def _same_class(current: Any, name: str, where: str) -> None:
    if current is None or type(current).__name__ != name:
        raise CheckpointError(f"{where}: holds a {str(name)[:40]}, the run file makes a {type(current).__name__}")


def _digest(state_json: bytes, arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256(state_json)
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}:{a.dtype.str}:{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def dumps(state) -> bytes:
    """The ``.npz`` bytes of ``state`` (a RunState); if some of it is not data, a marker saying what."""
    enc = _Encoder()
    meta = {"format": FORMAT, "evoplan_version": __version__, "fingerprint": state.fingerprint,
            "generation": int(state.algorithm.generation), "resumable": True, "reason": None}
    try:
        meta["state"] = enc(state, "state")
    except NotData as e:
        enc.arrays.clear()
        meta.update(resumable=False, reason=f"the {state.algorithm.name} algorithm keeps {e}, which a "
                                             "data-only checkpoint cannot store")
    body = json.dumps(meta).encode()
    buf = io.BytesIO()
    np.savez(buf, __state__=np.frombuffer(body, dtype=np.uint8),
             __sha256__=np.frombuffer(_digest(body, enc.arrays).encode(), dtype=np.uint8), **enc.arrays)
    return buf.getvalue()


def read(path) -> tuple[dict, dict[str, np.ndarray]]:
    """``(meta, arrays)`` of a checkpoint file, its checksum verified; ``CheckpointError`` if not."""
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError, KeyError) as e:
        raise CheckpointError(f"not a readable checkpoint ({type(e).__name__}: {str(e)[:80]})") from None
    body, digest = arrays.pop("__state__", None), arrays.pop("__sha256__", None)
    if body is None or digest is None:
        raise CheckpointError("not an evoplan checkpoint (no state or checksum)")
    if _digest(body.tobytes(), arrays) != digest.tobytes().decode("ascii", "replace"):
        raise CheckpointError("checksum mismatch: the file was changed or damaged after it was written")
    try:
        meta = json.loads(body.tobytes().decode())
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise CheckpointError(f"unreadable state ({e})") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise CheckpointError(f"not an {FORMAT} file")
    if meta.get("evoplan_version") != __version__:
        raise CheckpointError(f"checkpoint of evoplan {str(meta.get('evoplan_version'))[:20]}, this is {__version__}")
    return meta, arrays


def load_into(meta: dict, arrays: dict[str, np.ndarray], fresh):
    """The stored state loaded into ``fresh`` (a new RunState built from the same run file)."""
    if not meta.get("resumable"):
        raise CheckpointError(str(meta.get("reason"))[:300])
    return _decode(meta["state"], arrays, fresh, "state")
