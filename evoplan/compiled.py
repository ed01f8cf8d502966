"""When the core's compiled (numba) kernels pay for themselves in a process.

The core's hot loops have a compiled form and a numpy form that give the same numbers
bit for bit:

- the evaluation cache's key index (``key_index.py`` against a ``dict``; a batch's look-up
  with its known values and rows to evaluate, and its store, one pass each);
- the population's stable order (``operators/ranking_kernels.py``, a radix sort, from 512
  values) and the roulette wheel (``operators/selection_kernels.py``, a guide table);
- the GA's breeding of children from their parents (``operators/breeding_kernels.py``
  against the crossover and mutation operators' masks), and for the paper's default
  operators the whole step from ranks to children in one pass;
- VEGA's infection pairs, infection round, transductions and virus bookkeeping
  (``operators/viral_kernels.py`` against ``operators/viral.py`` and
  ``operators/viral_outcome.py``).

The compiled forms are faster per row, but a process pays once to load numba and dispatch
them. Measured on the 2-core host in fresh processes (GA on Kubota's function, pop 200, a
100 000-entry cache, whole-process CPU seconds, medians of 3, session of 2026-12-07 with
every form above): numpy 0.94 s at 2000 generations and 2.94 s at 12 000 (200 us a
generation), compiled 1.16 s and 2.15 s (99 us a generation): the load costs 0.42 s and
pays back after about 4200 generations, 1.7 M rows as counted below (the cache's 200 and
the 199 children a generation). (Before the ranking, wheel, one-pass breeding and virus
forms: 187 against 111 us a generation, a 0.53 s load, 2.8 M rows.)

:func:`use_compiled` is the rule, one for the process (the cost is the process's):

- numba already loaded (a toolpath problem's kernels, or an earlier long run): compiled, as
  the load is paid;
- else numpy, until the process has put :data:`SWITCH_ROWS` rows through these loops (the
  cache's rows, the children bred, and VEGA's infections too); then compiled. That is the
  break-even above, so a run never pays much more than twice what the better choice in
  hindsight would have cost (the ski-rental rule).

The choice changes time, never numbers. :func:`set_mode` fixes it (``always`` / ``never``) for
benchmarks and tests; :func:`forced` for the length of a ``with`` block.
"""

from __future__ import annotations

import sys
from contextlib import contextmanager

__all__ = ["SWITCH_ROWS", "MODES", "use_compiled", "set_mode", "forced"]

SWITCH_ROWS = 1_700_000
MODES = ("auto", "always", "never")

_mode = "auto"
_rows = 0


def use_compiled(rows: int = 0) -> bool:
    """Whether to use the compiled form for a batch of ``rows`` rows (counted towards
    :data:`SWITCH_ROWS`)."""
    global _rows
    if _mode != "auto":
        return _mode == "always"
    _rows += rows
    return _rows >= SWITCH_ROWS or "numba" in sys.modules


def set_mode(mode: str) -> str:
    """Fix the rule (``auto``, ``always`` or ``never``); returns the previous mode."""
    global _mode
    if mode not in MODES:
        raise ValueError(f"compiled mode: expected one of {', '.join(MODES)}, got {mode!r}")
    previous, _mode = _mode, mode
    return previous


@contextmanager
def forced(mode: str):
    """The rule fixed to ``mode`` inside a ``with`` block, the previous one restored after."""
    previous = set_mode(mode)
    try:
        yield
    finally:
        set_mode(previous)
