"""The part: parametric surfaces batched over (u, v) (Fountas Eq. 14, Choi's Bezier patch,
Bezier and B-spline nets), their checks as graphs over XY, surfaces from plain data, and the
chord deviation of a straight move from a surface curve."""
