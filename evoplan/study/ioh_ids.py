"""Which IOHprofiler function a study problem is: suite, function id, function name, instance.

IOHanalyzer and iohinspector group runs by function id and dimension, so an id must mean the
same function in every study, whatever the problem's position or label in the study file.

- **BBOB** (``bbob-f<k>`` or ``bbob-f<k>-i<i>``, or ``evoplan.study.bbob:BBOB`` with
  ``function``/``instance`` parameters): suite ``BBOB``, function id ``k`` (1..24), ioh's
  function name (``Rastrigin`` for f3), instance ``i``: the ids COCO and ioh use.
- **Every other problem**: suite ``evoplan``, instance 1, and a function id in
  ``NON_BBOB_IDS`` (30000..59999, above every id of ioh's own suites and inside the 16-bit ids
  iohinspector keeps): ``30000 + crc32(key) mod 30000``, where the key is the problem's name,
  followed by its parameters as sorted JSON when it has any (``n_var`` left out: the dimension
  is the ``DIM`` of the data, not part of the function). The same problem therefore has the
  same id in every study; ``kubota`` is always f41644. The function name is the study's label for it.
  Two different problems of one study whose keys fall on the same id (probability about
  1/30000 per pair) are told apart by giving the later one, in the study's order, the next
  free id.
"""

from __future__ import annotations

import json
import zlib
from dataclasses import dataclass
from typing import Any, Iterable

from .bbob import TARGET, resolve_problem_name

NON_BBOB_IDS = range(30000, 60000)


@dataclass(frozen=True)
class Function:
    suite: str
    id: int
    name: str
    instance: int


def bbob_name(k: int) -> str:
    """ioh's name of BBOB function ``k`` (``Rastrigin`` for 3); ``bbob_f<k>`` without ioh."""
    try:
        import ioh
    except ImportError:
        return f"bbob_f{k}"
    return str(ioh.ProblemClass.BBOB.problems[int(k)])


def problem_key(name: str, params: dict[str, Any]) -> str:
    """The text a non-BBOB problem's id is hashed from (see the module docstring)."""
    rest = {k: v for k, v in params.items() if k != "n_var"}
    return name if not rest else f"{name} {json.dumps(rest, sort_keys=True, default=str)}"


def hashed_id(key: str) -> int:
    """``30000 + crc32(key) mod 30000``: a stable id in ``NON_BBOB_IDS``."""
    return NON_BBOB_IDS.start + zlib.crc32(key.encode()) % len(NON_BBOB_IDS)


def functions(problems: Iterable[tuple[str, str, dict[str, Any]]]) -> dict[str, Function]:
    """``{label: Function}`` for a study's problems, given as ``(label, name, params)`` in the
    study's order."""
    out: dict[str, Function] = {}
    taken: dict[int, str] = {}
    for label, name, params in problems:
        target, resolved = resolve_problem_name(name, params)
        if target == TARGET:
            k = int(resolved.get("function", 1))
            out[label] = Function("BBOB", k, bbob_name(k), int(resolved.get("instance", 1)))
            continue
        key = problem_key(name, params)
        fid = hashed_id(key)
        while taken.get(fid, key) != key:
            fid = NON_BBOB_IDS.start + (fid + 1 - NON_BBOB_IDS.start) % len(NON_BBOB_IDS)
        taken[fid] = key
        out[label] = Function("evoplan", fid, label, 1)
    return out
