"""From decisions to a toolpath: zoning, per-zone feed direction, passes, CC points,
orientation, CL points and the moves that join them."""
