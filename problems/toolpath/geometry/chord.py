"""Chord error (chordal deviation) between consecutive CC points.

Fountas et al. Eq. 1-3: rho_i = 2 sin(theta/2) / L_i (Eq. 1, the curvature of the circle
through two points whose normals differ by theta), L_i the 3D chord (Eq. 2), and
C_e = rho - sqrt(rho^2 - (L/2)^2) (Eq. 3). Eq. 3 as printed mixes a curvature with a radius
and takes the square root of a negative number for realistic data; it is NOT implemented.
The sagitta it means (docs/toolpath_formulas.md) is

    R_c = L / (2 sin(theta/2)),  C_e = R_c - sqrt(R_c^2 - L^2/4) = (L/2) tan(theta/4) ~ kappa L^2/8

(:func:`chord_error_normals`). Caveat: theta = arccos(n1.n2) also counts the twist of the
normal about the path, which on Fountas' surface doubles the error (0.0083 mm instead of the
true 0.0040 mm at a 5 mm step). The engine therefore measures the true curve-to-chord
distance (:func:`chord_deviation`): the pass curve is evaluated at the middle of each segment
(middle of its feed coordinate) and its distance to the chord is taken; for a curve of slowly
varying curvature the deviation is a parabola in the feed coordinate peaking at that middle,
so this is the maximum deviation to second order.
"""

from __future__ import annotations

import numpy as np

from .vectors import cross_rows, row_norms

__all__ = ["chord_deviation", "chord_error_normals", "chord_error_curvature",
           "circle_curvature_eq1"]


def chord_deviation(a, m, b) -> np.ndarray:
    """Distance of points m from the chords a-b (lines through a and b): (n, 3) x3 -> (n,).

    With m the pass curve's point at the middle of the segment, this is the chord error.
    A zero-length chord gives |m - a|.
    """
    d = b - a
    am = m - a
    ll = np.einsum("ij,ij->i", d, d)
    cr = cross_rows(am, d)
    with np.errstate(divide="ignore", invalid="ignore"):
        dist = np.sqrt(np.einsum("ij,ij->i", cr, cr) / ll)
    chord = ll > 0
    if chord.all():  # no zero-length chord: the norms below are not needed
        return dist
    return np.where(chord, dist, row_norms(am))


def circle_curvature_eq1(theta, L):
    """Fountas Eq. 1: rho = 2 sin(theta/2) / L, the curvature (1/mm) of the circle through
    two points a chord L apart whose normals make the angle theta (radians)."""
    return 2.0 * np.sin(np.asarray(theta, float) / 2.0) / np.asarray(L, float)


def chord_error_normals(L, theta):
    """Corrected Fountas Eq. 3: sagitta (L/2) tan(theta/4) of the circle of Eq. 1 (mm).

    theta from arccos(n1.n2) includes the normal's twist about the path (see module doc).
    """
    return 0.5 * np.asarray(L, float) * np.tan(np.asarray(theta, float) / 4.0)


def chord_error_curvature(L, kappa):
    """Sagitta of a chord L on a circle of curvature |kappa|: (L^2/4)|k| / (1 + sqrt(1 - (Lk/2)^2)).

    Equals R - sqrt(R^2 - L^2/4) with R = 1/|kappa| (bending-only form, ~ kappa L^2 / 8);
    a straight line (kappa = 0) gives 0. Requires |kappa| L <= 2.
    """
    L = np.asarray(L, float)
    k = np.abs(np.asarray(kappa, float))
    return 0.25 * L * L * k / (1.0 + np.sqrt(1.0 - (0.5 * L * k) ** 2))
