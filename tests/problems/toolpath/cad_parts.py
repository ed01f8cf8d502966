"""OCCT shapes for the STEP / IGES tests: a rational B-spline face, a cylinder face, a box."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("OCP")

from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace  # noqa: E402
from OCP.Geom import Geom_BSplineSurface  # noqa: E402
from OCP.gp import gp_Pnt  # noqa: E402
from OCP.OCP.collections import Array1_double, Array1_int, Array2_double, Array2_gp_Pnt  # noqa: E402


def array1(values, cls=Array1_double):
    a = cls(1, len(values))
    for k, x in enumerate(values):
        a.SetValue(k + 1, x)
    return a


def nurbs_face_surface(seed: int = 0):
    """A rational bicubic-by-quadratic Geom_BSplineSurface over u in [2, 5], v in [-1, 3]
    with inner knots, random weights in [0.6, 1.6] and a gentle free-form height."""
    rng = np.random.default_rng(seed)
    nu, nv = 6, 4
    poles, weights = Array2_gp_Pnt(1, nu, 1, nv), Array2_double(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            x, y = 12.0 * i, 9.0 * j
            poles.SetValue(i + 1, j + 1, gp_Pnt(x, y, 5 + rng.uniform(-2, 2)))
            weights.SetValue(i + 1, j + 1, float(rng.uniform(0.6, 1.6)))
    return Geom_BSplineSurface(poles, weights, array1([2.0, 3.5, 4.2, 5.0]),
                               array1([-1.0, 1.2, 3.0]), array1([4, 1, 1, 4], Array1_int),
                               array1([3, 1, 3], Array1_int), 3, 2, False, False)


def face_of(surface):
    """The untrimmed face of a Geom surface (its natural bounds)."""
    return BRepBuilderAPI_MakeFace(surface, 1e-7).Face()
