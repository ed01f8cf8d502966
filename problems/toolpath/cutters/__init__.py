"""Cutters: one abstraction for flat-end, ball-end, toroidal (bull-nose) and tapered ball-end
mills.

- ``base``: :class:`Cutter` (the primitives a shape implements, and what is written once
  on them: CC -> tip offset, drop-cutter, R_eff, the APT statement) and the registry
  (:func:`register`, :func:`make_cutter`).
- ``shapes``: the flat-end, ball-end and toroidal cutters (one torus geometry).
- ``tapered``: the tapered ball-end mill (a cone of half-angle beta ending in a ball).
- ``effective_radius``: R_eff (Djebali Eq. 1, the general lead/tilt form), once.
- ``silhouette``: the swept cross-section (silhouette) of the torus-family shapes, once,
  for the 5-axis scallop tables and the 3-axis zoning step-over.
- ``drop`` (+ ``drop_rim``): the 3-axis drop-cutter against an exact parametric surface.
- ``surface_grid``: the dense (u, v) grid with an XY KD-tree, and the inverse map XY -> (u, v).

A new shape (conical, barrel, ...) is one subclass of :class:`Cutter` decorated with
:func:`register` (``tapered`` is one); nothing outside this package branches on the shape.
"""

from . import shapes as _shapes  # noqa: F401  (registers the shapes)
from . import tapered as _tapered  # noqa: F401
from .base import (CUTTERS, Cutter, cutter_from_apt, cutter_from_dict, cutter_from_tool,
                   cutter_names, make_cutter, register)
from .shapes import BallEndCutter, FlatEndCutter, ToroidalCutter
from .tapered import TaperedBallCutter

__all__ = ["CUTTERS", "Cutter", "BallEndCutter", "FlatEndCutter", "ToroidalCutter",
           "TaperedBallCutter", "cutter_from_apt", "cutter_from_dict", "cutter_from_tool",
           "cutter_names", "make_cutter", "register"]
