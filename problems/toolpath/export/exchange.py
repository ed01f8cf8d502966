"""Geometry exchange: DXF (ezdxf) of the surface mesh and the toolpaths, STL (numpy-stl).

- ``surface_dxf``: the surface sampled on an n x m parametric grid as one DXF polygon mesh
  (POLYLINE with M x N vertices, the mesh form Abbas' DXF carries), layer ``SURFACE``.
- ``toolpaths_dxf``: every operation on its own layer, each section (pass or layer) one 3D
  polyline of its cutting and plunge moves, and the rapids on ``<layer>_RAPID`` (dashed).
  Every layer is declared in the LAYER table with its colour.
- ``surface_stl``: the same grid split into two triangles per cell, binary STL, normals on
  the tool side.

Each returns the file's bytes (the caller writes it atomically).
"""

from __future__ import annotations

import io

import numpy as np

from .toolpath import Toolpath

LAYER_COLORS = (8, 1, 3, 5, 6, 4, 2)  # AutoCAD colour indices: grey surface, then red, green, blue...


def surface_grid(surface, n: int = 41, m: int = 41) -> np.ndarray:
    """(n, m, 3) surface points on a uniform (u, v) grid."""
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, m), indexing="ij")
    return surface.points(u.ravel(), v.ravel()).reshape(n, m, 3)


def _dxf_bytes(doc) -> bytes:
    buf = io.StringIO()
    doc.write(buf)
    return buf.getvalue().encode("utf-8")


def surface_dxf(surface, n: int = 41, m: int = 41) -> bytes:
    """The surface as a DXF polygon mesh of n x m vertices."""
    import ezdxf

    grid = surface_grid(surface, n, m)
    doc = ezdxf.new("R2010", units=ezdxf.units.MM)
    doc.layers.add("SURFACE", color=LAYER_COLORS[0])
    mesh = doc.modelspace().add_polymesh((n, m), dxfattribs={"layer": "SURFACE"})
    for i in range(n):
        for j in range(m):
            mesh.set_mesh_vertex((i, j), tuple(grid[i, j]))
    return _dxf_bytes(doc)


def toolpaths_dxf(toolpaths: dict[str, Toolpath]) -> bytes:
    """Each operation's sections as 3D polylines on layer NAME, rapids on NAME_RAPID."""
    import ezdxf

    doc = ezdxf.new("R2010", units=ezdxf.units.MM, setup=["linetypes"])
    msp = doc.modelspace()
    for i, (name, tp) in enumerate(toolpaths.items()):
        layer = name.upper()
        color = LAYER_COLORS[(i + 1) % len(LAYER_COLORS)]
        doc.layers.add(layer, color=color)  # declared in the LAYER table, as CAD viewers expect
        doc.layers.add(f"{layer}_RAPID", color=color, linetype="DASHED")
        for k in np.unique(tp.section[tp.section >= 0]):
            idx = np.flatnonzero(tp.section == k)
            runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
            for run in runs:
                pts = tp.tip[run[0] - 1:run[-1] + 1] if run[0] > 0 and not tp.rapid[run[0]] else tp.tip[run]
                if len(pts) >= 2:
                    msp.add_polyline3d([tuple(p) for p in pts], dxfattribs={"layer": layer})
        for n in np.flatnonzero(tp.rapid):
            if n > 0:
                msp.add_line(tuple(tp.tip[n - 1]), tuple(tp.tip[n]), dxfattribs={"layer": f"{layer}_RAPID"})
    return _dxf_bytes(doc)


def surface_stl(surface, n: int = 81, m: int = 81) -> bytes:
    """Binary STL of the surface grid, two triangles per cell, facing the tool side."""
    from stl import mesh as stl_mesh

    g = surface_grid(surface, n, m)
    a, b, c, d = g[:-1, :-1], g[1:, :-1], g[1:, 1:], g[:-1, 1:]
    tri = np.concatenate([np.stack([a, b, c], -2).reshape(-1, 3, 3), np.stack([a, c, d], -2).reshape(-1, 3, 3)])
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    mid = surface.normals(np.array([0.5]), np.array([0.5]))[0]
    if np.mean(normal @ mid) < 0:
        tri = tri[:, ::-1]
    out = stl_mesh.Mesh(np.zeros(len(tri), dtype=stl_mesh.Mesh.dtype))
    out.vectors[:] = tri
    buf = io.BytesIO()
    out.save("surface.stl", fh=buf, mode=stl_mesh.stl.Mode.BINARY)
    return buf.getvalue()
