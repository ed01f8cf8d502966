"""Finish-machining toolpath simulator for free-form surfaces (Fountas et al.; Djebali et al.).

Modules, one idea each:

- ``surface``, ``bezier``, ``bspline``: parametric surfaces, batched differential geometry.
- ``cutters``: the cutter shapes and their geometry (silhouette, R_eff, drop-cutter, APT);
  ``tools``: the tool database.
- ``pattern``: zig-zag parallel planes -> CC pattern (batched, with chord refinement).
- ``chord``, ``scallop``, ``length``: the criteria.
- ``simulator``: parameter sets -> CC patterns and every raw criterion.
- ``objective``: Fountas Eq. 9 with fixed normalization bounds.
- ``spec``: surfaces from plain data; ``problem``: the pymoo ``ToolpathProblem``.
"""

from .bezier import BezierSurface, choi_surface
from .bspline import BSplineSurface
from .problem import DEFAULT_RANGES, PARAM_NAMES, ToolpathProblem
from .simulator import CRITERIA, CCPattern, ToolpathSimulator
from .spec import parse_surface
from .surface import PolynomialSurface, Surface, fountas_surface
from .tools import DEFAULT_TOOLS, Tool, ToolDatabase, parse_tools

__all__ = [
    "BezierSurface", "BSplineSurface", "CCPattern", "CRITERIA", "DEFAULT_RANGES",
    "DEFAULT_TOOLS", "PARAM_NAMES", "PolynomialSurface", "Surface", "Tool", "ToolDatabase",
    "ToolpathProblem", "ToolpathSimulator", "choi_surface", "fountas_surface",
    "parse_surface", "parse_tools",
]
