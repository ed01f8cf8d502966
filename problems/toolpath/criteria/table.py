"""The one table of toolpath criteria: every name a plan is judged by, declared once.

Each :class:`Criterion` says its unit, whether it may be weighted in Fountas' Eq. 9 (a
weighted criterion must be finite: ``r_eff`` is infinite for a flat bottom, and
``objective`` is Eq. 9 itself), a one-line description, which family computes it
(``analytic``: ``criteria/analytic.py`` from the plan; ``objective``: ``criteria/objective.py``
from the others) and whether the cut simulation measures it under the same name
(``criteria/simulated.py`` replaces the analytic value under ``criteria: simulated``).

Everything that lists criteria reads this table: the weights and objectives validation,
the normalization bounds, the simulated names and the documentation's table (built by the
site hook ``docs/_hooks/criteria_table.py``). A removed name is not accepted: ``RENAMED``
holds the hint its one-line error gives (``weights.total_length: renamed eq4_total``).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Criterion", "CRITERIA", "RENAMED", "names", "check_name", "markdown_table"]


@dataclass(frozen=True)
class Criterion:
    """One criterion: ``name``, ``unit``, ``weightable`` (may enter Eq. 9), ``description``,
    ``family`` (``analytic`` | ``objective``), ``simulated`` (the cut simulation can
    measure it instead)."""

    name: str
    unit: str
    weightable: bool
    description: str
    family: str = "analytic"
    simulated: bool = False


_TABLE = (
    Criterion("cc_count", "points", True, "CC points on the part (the NC program's size)"),
    Criterion("n_passes", "passes", True, "pass planes, counted per zone"),
    Criterion("n_sections", "sections", True,
              "feed motions (a pass plane that leaves and re-enters its zone counts twice)"),
    Criterion("zones", "zones", True, "zones of the plan (1 without zoning)"),
    Criterion("chord_error_mean", "mm", True,
              "mean over the moves of the surface curve's largest distance from the chord"),
    Criterion("chord_error_max", "mm", True, "largest chord error of any move"),
    Criterion("r_eff", "mm", False,
              "effective cutting radius (smallest over the CC points); infinite for a flat "
              "bottom, so it cannot be weighted"),
    Criterion("scallop_max", "mm", True, "largest material height left mid-way between passes",
              simulated=True),
    Criterion("scallop_mean", "mm", True, "mean scallop over the CC points", simulated=True),
    Criterion("gouge_max", "mm", True,
              "deepest cut below the surface: between passes, and (5-axis) anywhere under "
              "the leaned cutter's end at a CC point", simulated=True),
    Criterion("undercut_max", "mm", True,
              "sharp-rim (flat-end) tools: the scallop of the rim and the inclined bottom; "
              "0 for the others", simulated=True),
    Criterion("machining_error", "mm", True,
              "largest chord error + scallop + gouge at a CC point (Fountas Fig. 1)",
              simulated=True),
    Criterion("machining_error_mean", "mm", True, "mean of the same over the CC points",
              simulated=True),
    Criterion("cutting_length", "mm", True, "length of the feed moves of the sections cut"),
    Criterion("link_length", "mm", True, "moves between consecutive sections of one zone"),
    Criterion("interzone_length", "mm", True, "moves from one zone's last section to the next zone"),
    Criterion("path_length", "mm", True, "cutting + link + inter-zone length"),
    Criterion("machining_time", "min", True,
              "the plan as the machine runs it: jerk-limited S-curve feed profile under the "
              "`dynamics` limits (default jerk 40 m/s^3, acceleration 6 m/s^2) at the "
              "programmed feed (the tool library's, else feed_rate), slowed at every direction "
              "change, zone changes as rapids"),
    Criterion("machining_time_nominal", "min", True,
              "path length / feed (the tool library's feed, else feed_rate; no rapids, no "
              "acceleration limits)"),
    Criterion("eq4_total", "mm", True,
              "Djebali Eq. 4: cutting length + (zones - 1) x delta_l"),
    Criterion("length_on_part_mm", "mm", True,
              "feed moves between CC points on the part, as the papers count (no runs "
              "past the edge)"),
    Criterion("length_papers_mm", "mm", True,
              "Djebali Eq. 4 on the part: length_on_part_mm + (zones - 1) x delta_l"),
    Criterion("objective", "-", False,
              "Fountas Eq. 9: the weighted sum of the normalized weighted criteria",
              family="objective"),
)

#: name -> :class:`Criterion`, in table order
CRITERIA: dict[str, Criterion] = {c.name: c for c in _TABLE}

#: a removed name -> its criterion's name (refused, with this hint)
RENAMED = {"total_length": "eq4_total"}


def names(*, weightable: bool | None = None, family: str | None = None,
          simulated: bool | None = None) -> tuple[str, ...]:
    """Criterion names in table order, filtered by the flags that are given."""
    return tuple(c.name for c in _TABLE
                 if (weightable is None or c.weightable == weightable)
                 and (family is None or c.family == family)
                 and (simulated is None or c.simulated == simulated))


def check_name(name, key: str, *, weightable: bool = False) -> str:
    """``name`` as a criterion name; ``ValueError`` starting with ``key`` for an unknown or
    renamed name, or, with ``weightable``, for one that cannot be weighted."""
    if isinstance(name, str) and name in RENAMED:
        raise ValueError(f"{key}: renamed {RENAMED[name]}")
    crit = CRITERIA.get(name) if isinstance(name, str) else None
    if crit is None:
        known = names(weightable=True) if weightable else tuple(CRITERIA)
        raise ValueError(f"{key}: unknown criterion {name!r} (known: {', '.join(known)})")
    if weightable and not crit.weightable:
        raise ValueError(f"{key}: {crit.name} cannot be weighted "
                         f"(weightable: {', '.join(names(weightable=True))})")
    return crit.name


def markdown_table() -> str:
    """The table as Markdown (criterion, unit, weightable, simulated, meaning)."""
    rows = ["| criterion | unit | weightable | cut simulation | meaning |",
            "|---|---|---|---|---|"]
    for c in _TABLE:
        rows.append(f"| `{c.name}` | {c.unit} | {'yes' if c.weightable else 'no'} | "
                    f"{'yes' if c.simulated else '-'} | {c.description} |")
    return "\n".join(rows) + "\n"
