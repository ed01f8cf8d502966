"""When the core's compiled (numba) kernels pay for themselves in a process.

The core's two hot loops have a compiled form and a numpy form that give the same numbers
bit for bit: the evaluation cache's key index (``key_index.py`` against a ``dict``) and VEGA's
infection round (``operators/viral_kernels.py`` against ``operators/viral_outcome.py``'s
matrix form). The compiled forms are about 5x faster per row (cache: 0.4 against 1.9 us a
row looked up and stored), but a process pays once to load numba and dispatch them: about
1.0-1.1 s of CPU on the 2-core host (numba's import 0.3-0.4 s, the first dispatch of a cached
function 0.6 s). A 200 x 200 GA run looks up 40 000 rows: in a fresh process the numpy forms
finish it before numba would have loaded.

:func:`use_compiled` is the rule, one for the process (the cost is the process's):

- numba already loaded (a toolpath problem's kernels, or an earlier long run): compiled, as
  the load is paid;
- else numpy, until the process has put :data:`SWITCH_ROWS` rows through these loops; then
  compiled. That is the break-even (1.05 s / 1.5 us a row), so a run never pays more than
  about twice what the better choice in hindsight would have cost (the ski-rental rule).

The choice changes time, never numbers. :func:`set_mode` fixes it (``always`` / ``never``) for
benchmarks and tests.
"""

from __future__ import annotations

import sys

__all__ = ["SWITCH_ROWS", "MODES", "use_compiled", "set_mode"]

SWITCH_ROWS = 700_000
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
