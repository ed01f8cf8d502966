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
MAX_DEPTH = 64  # nesting of the state's JSON (a run's state is about 8 levels deep)
MAX_MEMBERS = 10_000  # arrays in one checkpoint
MAX_BYTES = 8 * 2**30  # all arrays together


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


def _decode(value: Any, arrays, current: Any, where: str, depth: int = 0) -> Any:
    """``value`` as Python data; objects and generators are loaded *into* ``current``."""
    if depth > MAX_DEPTH:
        raise CheckpointError(f"{where}: nested deeper than {MAX_DEPTH} levels")
    out = _decode_value(value, arrays, current, where, depth + 1)
    _same_kind(current, out, where)
    return out


def _decode_value(value: Any, arrays, current: Any, where: str, depth: int) -> Any:
    if not isinstance(value, dict):
        return [_decode(v, arrays, None, where, depth) for v in value] if isinstance(value, list) else value
    if "$array" in value:
        if not isinstance(value["$array"], str) or value["$array"] not in arrays:
            raise CheckpointError(f"{where}: refers to an array the file does not hold")
        return arrays[value["$array"]]
    if "$tuple" in value:
        return tuple(_decode(v, arrays, None, where, depth) for v in value["$tuple"])
    if "$dict" in value:
        return {_freeze(_decode(k, arrays, None, where, depth)): _decode(v, arrays, None, where, depth)
                for k, v in value["$dict"]}
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
        return type(current).from_data(_decode(value["value"], arrays, None, where, depth))
    if "$object" in value:
        _same_class(current, value["$object"], where)
        values = {k: _decode(raw, arrays, getattr(current, k, None), f"{where}.{k}", depth)
                  for k, raw in value["attrs"]["$dict"]}
        if isinstance(current, Algorithm):
            current.load_state_dict(values)
        else:
            for k, v in values.items():
                setattr(current, k, v)
        return current
    raise CheckpointError(f"{where}: unexpected entry {sorted(value)[:3]}")


def _same_kind(current: Any, stored: Any, where: str) -> None:
    """A stored value must be of the kind the fresh state holds there (``None`` there: any data)."""
    if current is None or stored is current:
        return
    kinds = ((np.ndarray, np.ndarray), (bool, (bool, np.bool_)), (int, (int, np.integer)),
             (float, (int, float, np.integer, np.floating)), (str, str), ((list, tuple), (list, tuple)),
             (dict, dict))
    for fresh_type, allowed in kinds:
        if isinstance(current, fresh_type) and not (isinstance(current, int) and fresh_type is float):
            if isinstance(stored, bool) and fresh_type is not bool:
                break
            if isinstance(stored, allowed):
                if isinstance(current, np.ndarray) and (stored.ndim != current.ndim
                                                        or stored.dtype.kind != current.dtype.kind):
                    raise CheckpointError(f"{where}: holds a {stored.ndim}-d {stored.dtype} array where the "
                                          f"run keeps a {current.ndim}-d {current.dtype} one")
                return
            break
    else:
        return  # objects (rng, cache, algorithm) are checked by class where they are loaded
    raise CheckpointError(f"{where}: holds a {type(stored).__name__} where the run keeps a "
                          f"{type(current).__name__}")


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


def check_members(path) -> None:
    """Refuse, before anything is allocated, a checkpoint whose arrays are not what evoplan
    writes: every member a stored (uncompressed) ``.npy`` whose header declares a numeric dtype
    and a size its member really holds, and at most ``MAX_BYTES`` in all. A 1 KB file whose
    header claims 10^12 floats is refused here, not by a ``MemoryError``."""
    total = 0
    with zipfile.ZipFile(path) as zf:
        members = zf.infolist()
        if len(members) > MAX_MEMBERS:
            raise CheckpointError(f"{len(members)} arrays, more than a run's state ever holds ({MAX_MEMBERS})")
        for info in members:
            name = info.filename
            if not name.endswith(".npy") or info.compress_type != zipfile.ZIP_STORED:
                raise CheckpointError(f"member {name[:40]!r}: not an uncompressed .npy array")
            with zf.open(info) as f:
                version = np.lib.format.read_magic(f)
                if version not in ((1, 0), (2, 0), (3, 0)):
                    raise CheckpointError(f"member {name[:40]!r}: .npy version {version}")
                reader = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
                shape, _, dtype = reader(f, max_header_size=10_000)
            if dtype.kind not in ARRAY_KINDS or dtype.hasobject:
                raise CheckpointError(f"member {name[:40]!r}: an array of {str(dtype)[:20]} (not numbers)")
            declared = int(np.prod(shape, dtype=object)) * dtype.itemsize
            if declared > info.file_size:
                raise CheckpointError(f"member {name[:40]!r}: its header claims {declared:.3g} bytes "
                                      f"({shape}), the file holds {info.file_size}")
            total += declared
    if total > MAX_BYTES:
        raise CheckpointError(f"{total / 2**30:.1f} GiB of arrays, more than the {MAX_BYTES / 2**30:.0f} GiB "
                              "a checkpoint may hold")


def read(path) -> tuple[dict, dict[str, np.ndarray]]:
    """``(meta, arrays)`` of a checkpoint file, its sizes checked (:func:`check_members`) and its
    checksum verified; ``CheckpointError`` if not."""
    try:
        check_members(path)
        with np.load(path, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError, KeyError) as e:
        if isinstance(e, CheckpointError):
            raise
        raise CheckpointError(f"not a readable checkpoint ({type(e).__name__}: {str(e)[:80]})") from None
    body, digest = arrays.pop("__state__", None), arrays.pop("__sha256__", None)
    if body is None or digest is None:
        raise CheckpointError("not an evoplan checkpoint (no state or checksum)")
    if _digest(body.tobytes(), arrays) != digest.tobytes().decode("ascii", "replace"):
        raise CheckpointError("checksum mismatch: the file was changed or damaged after it was written")
    try:
        meta = json.loads(body.tobytes().decode())
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        raise CheckpointError(f"unreadable state ({str(e)[:80]})") from None
    except RecursionError:
        raise CheckpointError(f"the state is nested deeper than a run's state ever is") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise CheckpointError(f"not an {FORMAT} file")
    if meta.get("evoplan_version") != __version__:
        raise CheckpointError(f"checkpoint of evoplan {str(meta.get('evoplan_version'))[:20]}, this is {__version__}")
    return meta, arrays


def load_into(meta: dict, arrays: dict[str, np.ndarray], fresh):
    """The stored state loaded into ``fresh`` (a new RunState built from the same run file).

    The content is checked as it is loaded, since a checksum proves only that nobody changed the
    file after it was written, not who wrote it: nesting at most ``MAX_DEPTH`` levels, every
    referenced array present, and every stored value of the same kind as the fresh state's
    (an array where an array is, a number where a number is: :func:`_same_kind`). Counters are
    checked against the run's budget by the caller (``runner.resume_state``)."""
    if not meta.get("resumable"):
        raise CheckpointError(str(meta.get("reason"))[:300])
    if "state" not in meta:
        raise CheckpointError("no state in the checkpoint")
    try:
        return _decode(meta["state"], arrays, fresh, "state")
    except RecursionError:
        raise CheckpointError("the state is nested deeper than a run's state ever is") from None
    except (TypeError, ValueError, KeyError, IndexError, AttributeError) as e:
        if isinstance(e, CheckpointError):
            raise
        raise CheckpointError(f"a value of the state does not fit the run ({type(e).__name__}: "
                              f"{str(e)[:80]})") from None


COUNT_LIMIT = 2**53  # integers a float counts exactly: beyond it no run's counter can be
PER_GENERATION = 8  # evaluations per host (and virus) and generation that no algorithm exceeds


def check_counters(state, termination) -> None:
    """The loaded counters of ``state`` are what a run under ``termination`` can have reached:
    non-negative (the generation -1 before the initial population is evaluated), failures and cache hits within the evaluations, at most ``generations``
    generations, and evaluations within twice the budget (a generation may overshoot it, never
    double it). A crafted checkpoint with 1e30 evaluations is refused here, before any of it
    reaches ``best.json``."""
    generation = state.algorithm.generation
    counts = {"evaluations": state.evaluations, "failures": state.failures, "cache_hits": state.cache_hits,
              "stalled": state.stalled, "generation": generation}
    for name, value in counts.items():
        low = -1 if name == "generation" else 0  # generation -1: the initial population is still being evaluated
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not low <= value < COUNT_LIMIT:
            raise CheckpointError(f"state.{name}: {str(value)[:30]} is not a count a run can reach")
    if state.failures > state.evaluations:
        raise CheckpointError(f"state.failures: {state.failures} failures in {state.evaluations} evaluations")
    if termination.generations is not None and generation > termination.generations:
        raise CheckpointError(f"state.generation: {generation}, past the run's {termination.generations} generations")
    if termination.evaluations is not None and state.evaluations > 2 * termination.evaluations + len(state.algorithm.f):
        raise CheckpointError(f"state.evaluations: {state.evaluations}, far past the run's budget of "
                              f"{termination.evaluations}")
    viruses = len(getattr(state.algorithm, "life", ()))  # VEGA: each virus may infect every host
    per_generation = PER_GENERATION * (1 + viruses) * max(1, len(state.algorithm.f))
    for name in ("evaluations", "cache_hits"):
        if counts[name] > (generation + 1) * per_generation:
            raise CheckpointError(f"state.{name}: {counts[name]} in {generation} generations of "
                                  f"{len(state.algorithm.f)} hosts is more than any algorithm asks for")
    if len(state.history) > generation + 1:
        raise CheckpointError(f"state.history: {len(state.history)} rows for {generation} generations")
    _check_values(state)


def _check_values(state) -> None:
    """The state's values that a fresh state leaves empty (``None``, ``[]``) are of their kind."""
    best = state.best_g
    if best is not None:
        width = state.algorithm.G.shape[1] if getattr(state.algorithm, "G", np.zeros((0, 0))).ndim == 2 else None
        if not isinstance(best, np.ndarray) or best.ndim != 1 or (width and best.size != width):
            raise CheckpointError(f"state.best_g: not a genotype of this run ({type(best).__name__})")
    if state.stop_reason is not None and not (isinstance(state.stop_reason, str) and len(state.stop_reason) < 100):
        raise CheckpointError("state.stop_reason: not a stop reason")
    if not all(isinstance(e, str) for e in state.errors):
        raise CheckpointError("state.errors: not a list of messages")
    for name in ("history", "improvements"):
        for row in getattr(state, name):
            if not isinstance(row, (list, tuple)) or not all(
                    isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) for v in row):
                raise CheckpointError(f"state.{name}: a row that is not numbers")

