"""Surface zoning for 3-axis finishing (Djebali et al. 2015; Herraz et al. 2021).

Modules, one idea each:

- ``samples``: dense samples of the surface as a graph z(x, y) (slope, direction, Hessian).
- ``stepover``, ``profile``: the plane spacing keeping the scallop under h_c (R_eff circle of
  Djebali Eq. 1, or the exact swept profile of the torus), capped by the cutter's width;
  ``ScallopTarget`` is the pair (cutter, h_c) every zoning step takes (the cutter is a
  ``cutters.Cutter``).
- ``passes``: parallel planes restricted to a zone, its cutting length, a lower bound.
- ``features``: the n x m mesh and its per-cell features.
- ``kmeans``: Herraz's K-means zoning and connected zones; ``amas`` (+ ``amas_kernel``):
  Djebali's multi-agent zoning.
- ``methods``: the zoning-method registry (``single``, ``kmeans``, ``amas``: one module
  each, one ``ZoningMethod`` abstraction); ``merge``: the post-process after any method
  (minimum zone area, then Eq. 4 merging).
- ``direction``: per-zone feed direction (scipy bounded); ``plan``: the Eq. 4 pipeline.
- ``problem``: zoning as genes of a pymoo problem; ``figures``: the zone map.
"""

from .plan import METHODS, ZoningPlan, plan_zones
from .stepover import ScallopTarget

__all__ = ["METHODS", "ScallopTarget", "ZoningPlan", "plan_zones"]
