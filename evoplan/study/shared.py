"""What the runs of a study share: one problem object per configuration and worker process.

The runs of a study differ by algorithm and seed, not by problem: every run of a toolpath
problem would otherwise build the same surface grids, the same simulation design grid and,
as it evaluates, the same zone layouts (zoning, merging, per-zone direction tables), which the
planner memoizes per problem object. :func:`problem_for` keeps the problems it built, keyed by
a hash of their configuration (name and parameters), so a worker builds each once and every
later run on that worker reuses it, layouts included.

This is only done for the problems in :data:`SHARED`: those whose objective is a pure function
of the configuration and the decision row (their memos hold only what the configuration
determines), so a run gives the same numbers whether it finds the problem new or reused, on
any worker of any backend (serial, processes, Dask: each worker process has its own memo).
Other problems (a user's class may count calls or keep state) are built fresh for every run.

The memo keeps the :data:`MAX_KEPT` most recently used problems; :data:`STATS` counts, per
process, the problems ``built`` and ``reused``.
"""

from __future__ import annotations

import hashlib
import json
from collections import OrderedDict
from typing import Any

from ..problem_factory import make_problem

SHARED = frozenset({"toolpath"})  # pure objectives, costly to build
MAX_KEPT = 4
STATS = {"built": 0, "reused": 0}
_MEMO: OrderedDict[str, Any] = OrderedDict()


def config_key(name: str, params: dict[str, Any] | None) -> str:
    """A hash of a problem's configuration (its name and parameters, as plain data)."""
    text = json.dumps({"name": name, "params": params or {}}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def problem_for(name: str, params: dict[str, Any] | None):
    """The worker's problem for this configuration, built on first use; ``None`` when the
    problem is not shared (or cannot be built: :func:`evoplan.runner.prepare` then builds it
    and reports the error in its usual one line)."""
    if name not in SHARED:
        return None
    key = config_key(name, params)
    if key in _MEMO:
        _MEMO.move_to_end(key)
        STATS["reused"] += 1
        return _MEMO[key]
    try:
        problem = make_problem(name, params)
    except ValueError:
        return None
    STATS["built"] += 1
    _MEMO[key] = problem
    while len(_MEMO) > MAX_KEPT:
        _MEMO.popitem(last=False)
    return problem


def clear() -> None:
    """Forget every shared problem and reset the counts (tests; a fresh worker starts so)."""
    _MEMO.clear()
    STATS.update(built=0, reused=0)
