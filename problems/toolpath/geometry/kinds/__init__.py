"""The shipped surface types, one module each (importing them registers them, in this order)."""

from . import fountas, choi, bezier, bspline, nurbs, step, mesh  # noqa: F401,I001
