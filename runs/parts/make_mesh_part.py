"""The sample mesh part: a free-form height field over 90 x 60 mm written as a binary STL.

    python runs/parts/make_mesh_part.py                 # results/parts/wavy_mesh.stl
    python runs/parts/make_mesh_part.py --regenerate    # the committed runs/parts/wavy_mesh.stl
    python runs/parts/make_mesh_part.py --out PATH [--spacing MM]

z(x, y) = 12 + 5 g(x - 52, y - 34, 16) - 2.5 g(x - 22, y - 20, 12) + 0.002 (x - 45)(y - 30),
g(a, b, s) = exp(-(a^2 + b^2) / (2 s^2)): a bump, a hollow and a gentle saddle, the largest
curvature about 0.02 /mm. The grid of vertices is ``--spacing`` (default 0.75 mm) apart,
each square split into two triangles along alternating diagonals, wound so that the normals
point up. The file is the same bytes on every machine (numpy little-endian float32, no
time stamp), and ``runs/mesh_wavy_zoned_vega.yaml`` and ``runs/mesh_wavy_machine.yaml`` use it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
NAME = "wavy_mesh.stl"
SIZE = (90.0, 60.0)


def height(x, y):
    """The part's height z(x, y), mm (module docstring)."""
    def g(a, b, s):
        return np.exp(-(a * a + b * b) / (2.0 * s * s))
    return 12.0 + 5.0 * g(x - 52.0, y - 34.0, 16.0) - 2.5 * g(x - 22.0, y - 20.0, 12.0) \
        + 0.002 * (x - 45.0) * (y - 30.0)


def grid_triangles(xs, ys, z) -> np.ndarray:
    """(2 (nx-1)(ny-1), 3, 3) triangles of the height grid z (ny, nx), normals up; the
    diagonal of each square alternates like a chequer board."""
    X, Y = np.meshgrid(xs, ys)
    p = np.stack([X, Y, z], axis=-1)
    a, b, c, d = p[:-1, :-1], p[:-1, 1:], p[1:, 1:], p[1:, :-1]  # square corners, counter-clockwise
    iy, ix = np.meshgrid(np.arange(len(ys) - 1), np.arange(len(xs) - 1), indexing="ij")
    even = ((ix + iy) % 2 == 0)[..., None]
    t1 = np.where(even[..., None], np.stack([a, b, c], axis=2), np.stack([a, b, d], axis=2))
    t2 = np.where(even[..., None], np.stack([a, c, d], axis=2), np.stack([b, c, d], axis=2))
    return np.concatenate([t1.reshape(-1, 3, 3), t2.reshape(-1, 3, 3)])


def stl_bytes(triangles: np.ndarray) -> bytes:
    """A binary STL of (n, 3, 3) triangles (normals computed, header without a time stamp)."""
    tri = np.asarray(triangles, float)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.divide(n, length, out=np.zeros_like(n), where=length > 0)  # a degenerate one: 0
    rec = np.zeros(len(tri), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    rec["n"], rec["v"] = n, tri
    header = b"evoplan sample part: runs/parts/make_mesh_part.py".ljust(80, b" ")
    return header + np.uint32(len(tri)).tobytes() + rec.tobytes()


def part_bytes(spacing: float = 0.75) -> bytes:
    """The sample part's STL at vertex spacing ``spacing`` mm."""
    xs = np.linspace(0.0, SIZE[0], int(round(SIZE[0] / spacing)) + 1)
    ys = np.linspace(0.0, SIZE[1], int(round(SIZE[1] / spacing)) + 1)
    X, Y = np.meshgrid(xs, ys)
    return stl_bytes(grid_triangles(xs, ys, height(X, Y)))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", help=f"the STL (default results/parts/{NAME}; --regenerate: the committed one)")
    ap.add_argument("--regenerate", action="store_true", help=f"rewrite runs/parts/{NAME}")
    ap.add_argument("--spacing", type=float, default=0.75, help="vertex spacing, mm (default 0.75)")
    args = ap.parse_args(argv)
    out = Path(args.out) if args.out else (HERE if args.regenerate else Path("results/parts")) / NAME
    out.parent.mkdir(parents=True, exist_ok=True)
    data = part_bytes(args.spacing)
    out.write_bytes(data)
    print(f"{out}: {(len(data) - 84) // 50} triangles, {len(data)} bytes")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
