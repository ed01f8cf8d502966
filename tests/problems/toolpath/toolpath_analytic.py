"""Analytic test surfaces (exact planes, cylinders, spheres) for the toolpath tests.

The surfaces are graphs z = h(x, y) over a rectangle with x = x0 + (x1 - x0) u and
y = y0 + (y1 - y0) v, implemented with closed-form derivatives, so every curvature and
sagitta in the tests is known by hand.
"""

from __future__ import annotations

import numpy as np

from evoplan.problems.toolpath.geometry.surface import Jet, Surface


class GraphSurface(Surface):
    """z = h(x, y); subclasses give h and its derivatives up to order 2."""

    def __init__(self, x0, x1, y0, y1):
        self.x0, self.ax, self.y0, self.ay = x0, x1 - x0, y0, y1 - y0
        self._orient(None)

    def height(self, x, y):  # pragma: no cover - abstract
        raise NotImplementedError

    def jet(self, u, v, order=2):
        u = np.asarray(u, float)
        v = np.asarray(v, float)
        x = self.x0 + self.ax * u
        y = self.y0 + self.ay * v
        h, hx, hy, hxx, hxy, hyy = self.height(x, y)
        z0 = np.zeros_like(x)
        p = np.stack([x, y, h], -1)
        if order == 0:
            return Jet(p)
        su = np.stack([z0 + self.ax, z0, self.ax * hx], -1)
        sv = np.stack([z0, z0 + self.ay, self.ay * hy], -1)
        if order == 1:
            return Jet(p, su, sv)
        return Jet(p, su, sv, np.stack([z0, z0, self.ax ** 2 * hxx], -1),
                   np.stack([z0, z0, self.ax * self.ay * hxy], -1),
                   np.stack([z0, z0, self.ay ** 2 * hyy], -1))


class Plane(GraphSurface):
    """z = a x + b y + c."""

    def __init__(self, x0=0.0, x1=100.0, y0=0.0, y1=60.0, a=0.0, b=0.0, c=0.0):
        self.a, self.b, self.c = a, b, c
        super().__init__(x0, x1, y0, y1)

    def height(self, x, y):
        z = np.zeros_like(x)
        return self.a * x + self.b * y + self.c, z + self.a, z + self.b, z, z, z


class Cylinder(GraphSurface):
    """z = s sqrt(rho^2 - q^2), q = x (axis along Y) or y (axis along X).

    s = +1: a convex bump seen from above; s = -1: a concave trough."""

    def __init__(self, rho, axis="y", sign=1.0, half=30.0, length=60.0):
        self.rho, self.axis, self.s = rho, axis, sign
        if axis == "y":
            super().__init__(-half, half, 0.0, length)
        else:
            super().__init__(0.0, length, -half, half)

    def height(self, x, y):
        q = x if self.axis == "y" else y
        g = np.sqrt(self.rho ** 2 - q * q)
        s = self.s
        dq, dqq = -q / g, -(self.rho ** 2) / g ** 3
        z = np.zeros_like(x)
        if self.axis == "y":
            return s * g, s * dq, z, s * dqq, z, z
        return s * g, z, s * dq, z, z, s * dqq


class Sphere(GraphSurface):
    """z = s sqrt(rho^2 - x^2 - y^2) over [-half, half]^2: s = +1 a cap, -1 a bowl."""

    def __init__(self, rho, sign=1.0, half=20.0):
        self.rho, self.s = rho, sign
        super().__init__(-half, half, -half, half)

    def height(self, x, y):
        g = np.sqrt(self.rho ** 2 - x * x - y * y)
        s = self.s
        return (s * g, -s * x / g, -s * y / g, -s * (g * g + x * x) / g ** 3,
                -s * x * y / g ** 3, -s * (g * g + y * y) / g ** 3)
