"""Make the sample STEP part: a block with a sculptured B-spline top, a drilled hole and a notch.

The part (mm): a 100 x 80 block, its bottom at z = 0 and its top a bicubic B-spline surface
(8 x 7 poles, z from about 27 to 38), a vertical hole of radius 8 through it at (65, 40) and a
30 x 20 notch cut into its left side at y 30..50. So the top face is a trimmed free-form face
among 10 others (planes and the hole's cylinder): its outer wire is not convex (the notch)
and it has an inner wire (the hole): a pass plane y = 40 meets it in two stretches (the
notch shortens it, the hole splits it).

Built with OCCT (the ``cad`` extra): the B-spline face extruded downwards, intersected with
the block, the hole and the notch cut out. Usage::

    python runs/parts/make_step_part.py [--out PATH | --regenerate]

writes ``results/parts/sculpted_block.step`` under the current directory (``--regenerate``:
the committed ``runs/parts/sculpted_block.step`` beside this script).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

NAME = "sculpted_block.step"
LENGTH, WIDTH = 100.0, 80.0
HOLE = (65.0, 40.0, 8.0)  # centre x, y and radius
NOTCH = (0.0, 30.0, 30.0, 20.0)  # x, y, length along x, width along y


def top_height(x, y):
    """The designed height of the top (mm) at the poles: a saddle-like swell on a slope."""
    return 30.0 + 5.0 * np.sin(np.pi * x / 70.0) * np.cos(np.pi * y / 60.0) + 2.0 * (x / LENGTH) ** 2


def sculpted_block():
    """The part as an OCCT solid."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Cut
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Vec
    from OCP.OCP.collections import Array1_double, Array1_int, Array2_gp_Pnt

    nu, nv, deg = 8, 7, 3
    poles = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):  # the net overhangs the block by 10 mm: the block trims it
        for j in range(nv):
            x = -10.0 + (LENGTH + 20.0) * i / (nu - 1)
            y = -10.0 + (WIDTH + 20.0) * j / (nv - 1)
            poles.SetValue(i + 1, j + 1, gp_Pnt(x, y, float(top_height(x, y))))

    def clamped(n):
        inner = n - deg + 1
        knots, mults = Array1_double(1, inner), Array1_int(1, inner)
        for k in range(inner):
            knots.SetValue(k + 1, k / (inner - 1))
            mults.SetValue(k + 1, deg + 1 if k in (0, inner - 1) else 1)
        return knots, mults

    (ku, mu), (kv, mv) = clamped(nu), clamped(nv)
    top = Geom_BSplineSurface(poles, ku, kv, mu, mv, deg, deg, False, False)
    prism = BRepPrimAPI_MakePrism(BRepBuilderAPI_MakeFace(top, 1e-7).Face(),
                                  gp_Vec(0, 0, -60)).Shape()
    block = BRepAlgoAPI_Common(prism, BRepPrimAPI_MakeBox(LENGTH, WIDTH, 50.0).Shape()).Shape()
    hx, hy, hr = HOLE
    hole = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(hx, hy, -1), gp_Dir(0, 0, 1)), hr, 60.0).Shape()
    block = BRepAlgoAPI_Cut(block, hole).Shape()
    nx, ny, nl, nw = NOTCH
    notch = BRepPrimAPI_MakeBox(gp_Pnt(nx - 1, ny, -1), nl + 1, nw, 60.0).Shape()
    return BRepAlgoAPI_Cut(block, notch).Shape()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None, help=f"the STEP file (default: results/parts/{NAME})")
    ap.add_argument("--regenerate", action="store_true",
                    help="rewrite the committed file beside this script")
    args = ap.parse_args(argv)
    here = Path(__file__).resolve().parent
    out = Path(args.out) if args.out else (here if args.regenerate else Path("results/parts")) / NAME
    out.parent.mkdir(parents=True, exist_ok=True)
    from evoplan.problems.toolpath.geometry.cad_faces import write_cad

    write_cad(sculpted_block(), out, "step")
    print(f"wrote {out} ({out.stat().st_size // 1024} KiB)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
