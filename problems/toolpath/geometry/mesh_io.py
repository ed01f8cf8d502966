"""Triangle meshes from STL, OBJ and PLY files (trimesh), checked to be a usable height field.

:func:`read_mesh` returns a :class:`TriangleMesh` in mm (``units`` scales the file's numbers),
with every triangle's normal turned to the tool side (+z) and zero-area triangles dropped, or
raises one line ``ValueError("<key>: <file>: <what is wrong> [near (x, y, z)]")`` when the
file cannot be used:

- unreadable, empty or corrupt (a binary STL whose header announces more triangles than the
  file holds, an ASCII STL cut short, a point cloud, NaN or infinite coordinates);
- degenerate: no triangle with an area, or all of them in a vertical plane;
- non-manifold: an edge shared by three or more triangles;
- not a height field over XY: a vertical wall (a triangle steeper than 89 degrees), an
  overhang (in a consistently wound mesh, a triangle facing down among ones facing up), or
  two sheets over the same (x, y) (found by :mod:`.mesh_raster` when the mesh is sampled).

A closed solid (a block with a sculptured top, as most CAD systems export a part) is read
with ``facing="up"``: its upward-facing triangles are the surface, its walls and bottom are
left out; an undercut then shows as two sheets over one (x, y).

trimesh is the ``mesh`` extra: without it the error names the extra (``evoplan/extras.py``).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["TriangleMesh", "read_mesh", "UNITS", "SUFFIXES", "MIN_NZ"]

#: mm per unit of a mesh file's numbers
UNITS = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "um": 1e-3, "in": 25.4, "inch": 25.4}
SUFFIXES = (".stl", ".obj", ".ply")
MIN_NZ = np.sin(np.radians(1.0))  # steepest accepted triangle: 89 degrees (as surface_checks.py)


@dataclass(frozen=True)
class TriangleMesh:
    """``vertices`` (nv, 3) mm, ``faces`` (nf, 3) vertex indices, each wound so that its
    normal points up (+z); ``normals`` (nf, 3) unit; ``label`` names the file in messages."""

    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    label: str
    dropped: int = 0  # zero-area triangles left out

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) of the vertices."""
        v = self.vertices
        return float(v[:, 0].min()), float(v[:, 0].max()), float(v[:, 1].min()), float(v[:, 1].max())

    def edges(self) -> np.ndarray:
        """(3 nf, 2) the triangles' edges (a, b) in winding order (edge k of face f at 3f + k)."""
        f = self.faces
        return np.stack([f, np.roll(f, -1, axis=1)], axis=2).reshape(-1, 2)


def _where(p) -> str:
    return f"at (x, y, z) = ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f})"


def _stl_problem(path: Path) -> str | None:
    """What is wrong with an STL file's framing, or None: a binary STL holds exactly the
    triangles its header announces (84 + 50 n bytes); an ASCII one starts ``solid`` and ends
    ``endsolid``."""
    size = path.stat().st_size
    if size == 0:
        return "the file is empty"
    with path.open("rb") as fh:
        head = fh.read(84)
        fh.seek(max(size - 512, 0))
        tail = fh.read().strip().lower()
    n = struct.unpack("<I", head[80:84])[0] if size >= 84 else None
    if n is not None and 84 + 50 * n == size:
        return None  # binary (its 80-byte header may start "solid" too)
    if head[:5].lower() == b"solid":
        if b"endsolid" in tail:
            return None
        return "corrupt ASCII STL: it ends without 'endsolid' (cut short?)"
    if n is None:
        return f"corrupt binary STL: {size} bytes, shorter than its 84-byte header"
    return (f"corrupt binary STL: the header announces {n} triangles ({84 + 50 * n} bytes), "
            f"the file has {size} bytes")


def _load(path: Path, key: str, label: str):
    """(vertices, faces) as trimesh reads them (vertices merged), or one line."""
    from evoplan.extras import require

    trimesh = require("trimesh", "mesh", "a mesh surface (type: mesh)")
    if path.suffix.lower() == ".stl":
        problem = _stl_problem(path)
        if problem:
            raise ValueError(f"{key}: {label}: {problem}")
    try:
        # NaN coordinates make trimesh's vertex merge warn ("invalid value encountered in
        # cast"); check_mesh refuses them in one line, so the warning is not printed too
        with np.errstate(invalid="ignore"):
            mesh = trimesh.load(str(path), file_type=path.suffix.lower().lstrip("."),
                                force="mesh", process=True)
        vertices = np.asarray(getattr(mesh, "vertices", ()), dtype=float).reshape(-1, 3)
        faces = np.asarray(getattr(mesh, "faces", ()), dtype=np.int64).reshape(-1, 3)
    except Exception as exc:  # a third-party parser: any failure is a bad file
        first = (str(exc).splitlines() or [type(exc).__name__])[0]
        raise ValueError(f"{key}: {label}: cannot read it as a {path.suffix[1:].upper()} mesh "
                         f"({first})") from None
    return vertices, faces


def read_mesh(source, key: str = "surface.file", base_dir=None, units: str = "mm",
              label: str | None = None, facing: str = "all") -> TriangleMesh:
    """The checked mesh of file ``source`` (relative to ``base_dir``), in mm (module doc);
    messages name it ``label`` (default: ``source`` as given)."""
    from .nets import resolve

    path = resolve(source, key, base_dir)
    label = str(source) if label is None else label
    if path.suffix.lower() not in SUFFIXES:
        raise ValueError(f"{key}: {label}: unsupported mesh file type {path.suffix!r} "
                         f"(use {', '.join(SUFFIXES)})")
    vertices, faces = _load(path, key, label)
    return check_mesh(vertices * UNITS[units], faces, key, label, facing)


def check_mesh(vertices, faces, key: str, label: str, facing: str = "all") -> TriangleMesh:
    """The :class:`TriangleMesh` of raw arrays, or one line saying why they cannot be used.

    ``facing="up"``: the mesh is a closed solid (every edge shared by two triangles, wound
    alike); its triangles facing up (outward normal above 1 degree from horizontal) are the
    surface: the part as the tool sees it from above. Its walls and bottom are left out."""
    vertices = np.asarray(vertices, float)
    faces = np.asarray(faces, np.int64)
    given = faces

    def fail(msg):
        raise ValueError(f"{key}: {label}: {msg}")

    if len(faces) == 0:
        fail("holds no triangles (empty, corrupt, or a point cloud)")
    if faces.min() < 0 or faces.max() >= len(vertices):
        fail("a triangle names a vertex that does not exist (corrupt file)")
    if not np.isfinite(vertices).all():
        fail("has NaN or infinite vertex coordinates (corrupt file)")
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    cross = np.cross(b - a, c - a)
    twice_area = np.linalg.norm(cross, axis=1)
    extent = float(np.ptp(vertices, axis=0).max())
    keep = twice_area > 1e-12 * max(extent, 1e-300) ** 2
    if not keep.any():
        fail(f"degenerate: none of its {len(faces)} triangles has an area")
    dropped = int((~keep).sum())
    faces, cross, twice_area = faces[keep], cross[keep], twice_area[keep]
    centroid = (a[keep] + b[keep] + c[keep]) / 3.0
    nz = cross[:, 2] / twice_area
    steep = np.abs(nz) < MIN_NZ
    if steep.all():
        fail("degenerate: every triangle stands vertical (no area seen from above)")
    _check_manifold(faces, vertices, fail)
    if facing == "up":
        cross, nz = _outward(given, faces, vertices, cross, nz, fail)
        up = nz > MIN_NZ
        if not up.any():
            fail("facing: up: no triangle of the solid faces up")
        faces, cross, twice_area, centroid, nz = faces[up], cross[up], twice_area[up], centroid[up], nz[up]
        steep = np.zeros(len(faces), bool)
    if steep.any():
        i = int(np.flatnonzero(steep)[0])
        fail(f"not a height field over XY: vertical wall {_where(centroid[i])} (triangle {i}, "
             f"{np.degrees(np.arccos(min(abs(nz[i]), 1.0))):.1f} deg)")
    down = nz < 0
    if down.any() and not down.all() and _consistently_wound(faces):
        minority = down if down.sum() <= (~down).sum() else ~down
        i = int(np.flatnonzero(minority)[0])
        fail(f"not a height field over XY: overhang {_where(centroid[i])} (triangle {i} faces down)")
    faces = np.where(down[:, None], faces[:, ::-1], faces)  # every triangle faces up
    normals = cross * np.where(down, -1.0, 1.0)[:, None] / twice_area[:, None]
    used, faces = np.unique(faces, return_inverse=True)  # only the vertices of the triangles kept
    return TriangleMesh(vertices[used], np.ascontiguousarray(faces.reshape(-1, 3)), normals, label, dropped)


def _outward(given, faces, vertices, cross, nz, fail):
    """(cross, nz) of ``faces`` turned outward when the ``given`` triangles (zero-area ones
    included) close a consistently wound solid (its signed volume sum a . (b x c) / 6 is then
    positive), or one line saying why the mesh is no such solid."""
    edges = np.stack([given, np.roll(given, -1, axis=1)], axis=2).reshape(-1, 2)
    _, counts = np.unique(_edge_keys(edges, len(vertices)), return_counts=True)
    if (counts != 2).any():
        fail(f"facing: up takes a closed solid: {int((counts == 1).sum())} edges belong to one "
             "triangle only")
    if not _consistently_wound(given):
        fail("facing: up takes a closed solid wound consistently (its triangles' windings disagree)")
    a = vertices[faces[:, 0]]
    volume = float(np.einsum("ij,ij->i", a, cross).sum()) / 6.0
    return (cross, nz) if volume > 0 else (-cross, -nz)


def _edge_keys(edges: np.ndarray, n_vertices: int) -> np.ndarray:
    lo, hi = np.minimum(edges[:, 0], edges[:, 1]), np.maximum(edges[:, 0], edges[:, 1])
    return lo * n_vertices + hi


def _check_manifold(faces, vertices, fail) -> None:
    """Refuse an edge shared by three or more triangles (naming where)."""
    edges = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
    keys, inverse, counts = np.unique(_edge_keys(edges, len(vertices)), return_inverse=True,
                                      return_counts=True)
    if counts.max() > 2:
        e = int(np.flatnonzero(counts[inverse] > 2)[0])
        mid = vertices[edges[e]].mean(axis=0)
        fail(f"non-manifold: an edge of {counts[inverse[e]]} triangles {_where(mid)}")


def _consistently_wound(faces) -> bool:
    """Does every interior edge run one way in one triangle and the other way in the other?
    (Then the winding says which side is up, and a triangle facing down is an overhang.)"""
    edges = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
    n = int(faces.max()) + 1
    directed = edges[:, 0] * n + edges[:, 1]
    return len(np.unique(directed)) == len(directed)


def boundary_loops(mesh: TriangleMesh) -> list[np.ndarray]:
    """The mesh's boundary as closed loops of vertex indices (edges of one triangle only),
    the longest first."""
    edges = mesh.edges()
    keys = _edge_keys(edges, len(mesh.vertices))
    _, first, counts = np.unique(keys, return_index=True, return_counts=True)
    boundary = edges[first[counts == 1]]
    nxt: dict[int, list[int]] = {}
    for a, b in boundary.tolist():
        nxt.setdefault(a, []).append(b)
        nxt.setdefault(b, []).append(a)
    loops, seen = [], set()
    for start in nxt:
        if start in seen:
            continue
        loop, prev, here = [start], None, start
        seen.add(start)
        while True:
            step = [w for w in nxt[here] if w != prev and (w not in seen or w == start)]
            if not step or step[0] == start:
                break
            prev, here = here, step[0]
            loop.append(here)
            seen.add(here)
        if len(loop) >= 3:
            loops.append(np.array(loop))
    return sorted(loops, key=len, reverse=True)
