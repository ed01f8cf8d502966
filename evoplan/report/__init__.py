"""``evoplan report``: one self-contained HTML page of a results folder, read as data only.

The page opens offline: plotly's JavaScript is inlined once (``include_plotlyjs=True``) and
nothing is fetched. The folder's files are read as data (CSV, JSON, YAML, APT); the problem
named in ``config.yaml`` is never imported or built (see :mod:`evoplan.run_folder`).

- :mod:`.folder`: which kind of folder it is, and its files read with one-line errors.
- :mod:`.run`: a run's convergence, best decisions with units, and toolpath in 3D.
- :mod:`.study`: per-variant boxes of the final values, the summary and tests tables.
- :mod:`.simulate`: ``simulation.json``'s measures with units, the scallop distribution, the
  deviation PNGs embedded.
- :mod:`.machine`: an ``evoplan machine`` folder's operations, every path in 3D over
  ``surface.stl`` and the roughing layers (:mod:`.paths` reads the APT files, decimated for
  display by :mod:`.decimate` within a stated tolerance).
- :mod:`.deviation`, :mod:`.pareto`, :mod:`.studyfigs`: the deviation map in 3D and plan, the
  Pareto front with hover, a study's ECDFs and critical-difference diagrams.
- :mod:`.page`: the sections assembled into one HTML file.
"""

from __future__ import annotations

from pathlib import Path

from .folder import kind_of


def build(path: str | Path) -> str:
    """The HTML text of the report of the results folder ``path`` (``ConfigError`` on bad input)."""
    from .page import page

    folder = Path(path)
    kind = kind_of(folder)
    if kind == "run":
        from .run import sections
    elif kind == "study":
        from .study import sections
    elif kind == "machine":
        from .machine import sections
    else:
        from .simulate import sections
    return page(f"evoplan {kind}: {folder.resolve().name}", sections(folder))
