"""Benchmark: a STEP face loaded and its 0.1 mm design grid built, against Fountas' grid.

The face is the top of the sample part (runs/parts/sculpted_block.step, 11 faces, 169 KiB:
a trimmed bicubic B-spline face with a hole and a notch, 100 x 80 mm, 0.80 M cells at
0.1 mm). Each repeat, in one process: read the file and build the face (``type: step``,
``face: largest``: reading, the NURBS and its trimming loops, the height-field check), then
its 0.1 mm design grid (the numba spline path, the hole and notch cells masked, the edge
cells clipped); then, as the baseline, Fountas' surface (the polynomial numba path) on a grid
of the same number of cells. Importing OCCT (once per process) is timed apart. The figures
are CPU seconds of this process (one core: numba and BLAS single-threaded) and the ratio to
the baseline, medians over the repeats; on a shared host compare the ratios.
Run:  python runs/bench/step_face_speed.py [--repeats 5] [--grid 0.1]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
PART = ROOT / "runs" / "parts" / "sculpted_block.step"


def cpu(fn):
    t = time.process_time()
    out = fn()
    return out, time.process_time() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--grid", type=float, default=0.1)
    args = ap.parse_args()
    _, t_import = cpu(lambda: __import__("OCP.STEPControl"))
    from evoplan.problems.toolpath.geometry.spec import parse_surface
    from evoplan.problems.toolpath.simulation import design_grid

    spec = {"type": "step", "file": str(PART), "face": "largest"}
    fountas = parse_surface("fountas")
    design_grid(parse_surface(spec), 2.0)  # warm-up: numba kernels compiled or loaded
    design_grid(fountas, 2.0)
    rows = []
    for _ in range(args.repeats):
        surf, t_load = cpu(lambda: parse_surface(spec))
        grid, t_grid = cpu(lambda: design_grid(surf, args.grid))
        # the same number of cells on Fountas' part (its footprint 94.5 x 103.2 mm)
        h = float(np.sqrt(94.5 * 103.2 / grid.z.size))
        base, t_base = cpu(lambda: design_grid(fountas, h))
        rows.append((t_load, t_grid, t_base, grid.z.size, base.z.size, grid.inside.mean()))
    r = np.array(rows)
    med = np.median(r, axis=0)
    total = med[0] + med[1]
    print(f"OCCT import (once per process): {t_import:.2f} s CPU; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"STEP face load {med[0]:.2f} s + {args.grid:g} mm design grid {med[1]:.2f} s = "
          f"{total:.2f} s CPU (median of {args.repeats}; {int(med[3])} cells, "
          f"{med[5]:.1%} on the face)")
    print(f"baseline: Fountas' grid of {int(med[4])} cells {med[2]:.2f} s CPU; ratio "
          f"(load + grid) / baseline {total / med[2]:.2f}, grid alone {med[1] / med[2]:.2f} "
          f"(per repeat: {', '.join(f'{(a + b) / c:.2f}' for a, b, c in r[:, :3])})")


if __name__ == "__main__":
    main()
