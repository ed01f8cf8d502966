"""Benchmark: a 200 000-triangle STL loaded, checked and fitted (``type: mesh``), one core.

The sample part's surface (``runs/parts/make_mesh_part.py``) is written as a binary STL of
about 200 000 triangles into a temporary folder, twice: over the whole 90 x 60 mm rectangle
(the fit is one separable least-squares solve) and cut to the ellipse inscribed in it (about
157 000 triangles: samples off the mesh, so the fit is the banded sparse solve of
``mesh_fit.py``). Timed in one process, interleaved over the repeats so a load change on a
shared host hits every stage alike:

- **numpy baseline**: the file read with ``np.fromfile`` into its 50-byte records, and every
  triangle's normal and area computed: the least any STL reader does;
- **read**: trimesh's load (vertices merged) and the checks of ``mesh_io.py`` (manifold,
  degenerate, vertical walls, overhangs);
- **fit**: the least-squares bicubic height field of ``mesh_fit.py`` (sampling the mesh with
  the triangle rasterizer, overlap check included);
- **deviation**: the fit measured against the mesh at vertices, edge midpoints, centroids and
  samples.

The target is read + fit + deviation <= 5 s; the figure to quote is each stage's median and
its ratio to the baseline of the same run. trimesh's import is timed once, apart.
Run:  python runs/bench/mesh_speed.py [--repeats 5] [--triangles 200000]
"""

from __future__ import annotations

import argparse
import os
import runpy
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def numpy_baseline(path: Path) -> float:
    """Read the binary STL's records with numpy, compute normals and areas; returns the area."""
    rec = np.fromfile(path, dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")], offset=84)
    v = rec["v"].astype(float)
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    return float(0.5 * np.linalg.norm(n, axis=1).sum())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--triangles", type=int, default=200_000)
    args = ap.parse_args()

    part = runpy.run_path(str(ROOT / "runs" / "parts" / "make_mesh_part.py"))
    lx, ly = part["SIZE"]
    nx = int(round(np.sqrt(args.triangles / 2 * lx / ly)))  # squares along x, 2 triangles each
    spacing = lx / nx
    t = time.perf_counter()
    import trimesh  # noqa: F401

    import_s = time.perf_counter() - t
    from evoplan.problems.toolpath.geometry.mesh_fit import deviation, fit_height_field
    from evoplan.problems.toolpath.geometry.mesh_io import read_mesh

    xs = np.linspace(0.0, lx, nx + 1)
    ys = np.linspace(0.0, ly, int(round(ly / spacing)) + 1)
    X, Y = np.meshgrid(xs, ys)
    tri = part["grid_triangles"](xs, ys, part["height"](X, Y))
    c = tri.mean(axis=1)
    ellipse = ((c[:, 0] - lx / 2) / (lx / 2)) ** 2 + ((c[:, 1] - ly / 2) / (ly / 2)) ** 2 < 1
    stages = ("numpy baseline", "read", "fit", "deviation")
    with tempfile.TemporaryDirectory() as tmp:
        paths = {"rectangle": Path(tmp) / "part.stl", "ellipse": Path(tmp) / "ellipse.stl"}
        paths["rectangle"].write_bytes(part["stl_bytes"](tri))
        paths["ellipse"].write_bytes(part["stl_bytes"](tri[ellipse]))
        times = {(p, k): [] for p in paths for k in stages}
        results = {}
        for _ in range(args.repeats):
            for name, path in paths.items():
                t0 = time.perf_counter()
                numpy_baseline(path)
                t1 = time.perf_counter()
                mesh = read_mesh(path)
                t2 = time.perf_counter()
                fit = fit_height_field(mesh)
                t3 = time.perf_counter()
                dev = deviation(fit, mesh)
                t4 = time.perf_counter()
                for k, a, b in zip(stages, (t0, t1, t2, t3), (t1, t2, t3, t4)):
                    times[name, k].append(b - a)
                results[name] = (mesh, fit, dev)
    print(f"{args.repeats} repeats, one process, one thread (shared host: quote ratios); "
          f"import trimesh (once) {import_s:.3f} s")
    for name in paths:
        mesh, fit, dev = results[name]
        med = {k: float(np.median(times[name, k])) for k in stages}
        total = [sum(times[name, k][i] for k in stages[1:]) for i in range(args.repeats)]
        base = med["numpy baseline"]
        print(f"{name}: {len(mesh.faces)} triangles ({len(mesh.vertices)} vertices, spacing "
              f"{spacing:.4f} mm)")
        for k, m in med.items():
            print(f"  {k:26s} median {m:7.3f} s  ({m / base:6.1f}x the numpy baseline)")
        print(f"  read + fit + deviation     median {np.median(total):7.3f} s  (max {max(total):.3f} s; "
              f"{np.median(total) / base:.1f}x the baseline; target <= 5 s)")
        print(f"  fit: {fit.surface.coeffs.shape} coefficients, spacing {fit.spacing:.3f} mm, "
              f"largest deviation {dev.max_mm:.5f} mm over {dev.points} points")

if __name__ == "__main__":
    main()
