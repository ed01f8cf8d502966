"""Benchmark: a 200 000-triangle STL loaded, checked and fitted (``type: mesh``), one core.

The sample part's surface (``runs/parts/make_mesh_part.py``) is written as a binary STL of
about 200 000 triangles into a temporary folder. Timed in one process, interleaved over the
repeats so a load change on a shared host hits every stage alike:

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

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "part.stl"
        path.write_bytes(part["part_bytes"](spacing))
        times = {k: [] for k in ("numpy baseline", "read", "fit", "deviation")}
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            numpy_baseline(path)
            t1 = time.perf_counter()
            mesh = read_mesh(path)
            t2 = time.perf_counter()
            fit = fit_height_field(mesh)
            t3 = time.perf_counter()
            dev = deviation(fit, mesh)
            t4 = time.perf_counter()
            for k, a, b in zip(times, (t0, t1, t2, t3), (t1, t2, t3, t4)):
                times[k].append(b - a)
    med = {k: float(np.median(v)) for k, v in times.items()}
    total = [sum(times[k][i] for k in ("read", "fit", "deviation")) for i in range(args.repeats)]
    base = med["numpy baseline"]
    print(f"{len(mesh.faces)} triangles ({len(mesh.vertices)} vertices, spacing {spacing:.4f} mm), "
          f"{args.repeats} repeats, one process, one thread (shared host: quote ratios)")
    print(f"  import trimesh (once)      {import_s:7.3f} s")
    for k, m in med.items():
        print(f"  {k:26s} median {m:7.3f} s  ({m / base:6.1f}x the numpy baseline)")
    print(f"  read + fit + deviation     median {np.median(total):7.3f} s  (max {max(total):.3f} s; "
          f"{np.median(total) / base:.1f}x the baseline; target <= 5 s)")
    print(f"  fit: {fit.surface.coeffs.shape} coefficients, spacing {fit.spacing:.3f} mm, "
          f"largest deviation {dev.max_mm:.5f} mm over {dev.points} points")


if __name__ == "__main__":
    main()
