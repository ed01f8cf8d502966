"""Finish-machining toolpaths of free-form surfaces (Fountas et al.; Djebali et al.; Herraz et al.).

The folders follow the pipeline, each depending only on the ones before it:

- ``geometry/``: the part (parametric surfaces batched over (u, v), surfaces from plain
  data, graph checks, the chord deviation of a straight move).
- ``cutters/``: flat, ball, toroidal and tapered ball cutters (one abstraction, one
  registry); ``tools``: the one tool definition (a cutter, its id and cutting data).
- ``spec/``: the typed toolpath specification (a run file's ``params``), validated once.
- ``plan/``: decisions -> zones -> passes -> CC points -> orientation -> CL points
  (``PlanBatch``); ``zoning/`` holds the zoning methods.
- ``criteria/``: what a plan is worth (analytic, simulated) and Fountas Eq. 9.
- ``simulation/``: the cut simulation that referees the analytic criteria.
- ``export/``: APT, NC post-processors, DXF and STL; ``roughing/``: Abbas' layers.
- ``problem``: the pymoo ``ToolpathProblem`` (the one toolpath engine: ``Planner`` ->
  ``PlanBatch`` -> criteria), built from a ``ToolpathSpec``.
"""

from .geometry.bezier import BezierSurface, choi_surface
from .geometry.bspline import BSplineSurface
from .problem import DEFAULT_RANGES, PARAM_NAMES, ToolpathProblem
from .plan.batch import PlanBatch
from .plan.planner import Planner
from .geometry.spec import parse_surface
from .geometry.surface import PolynomialSurface, Surface, fountas_surface
from .spec import ToolpathSpec, parse_tools
from .tools import CHOI_TOOLS, DEFAULT_TOOLS, Tool, ToolDatabase

__all__ = [
    "BezierSurface", "BSplineSurface", "CHOI_TOOLS", "DEFAULT_RANGES", "DEFAULT_TOOLS", "PARAM_NAMES",
    "PlanBatch", "Planner", "PolynomialSurface", "Surface", "Tool", "ToolDatabase",
    "ToolpathProblem", "ToolpathSpec", "choi_surface", "fountas_surface",
    "parse_surface", "parse_tools",
]
