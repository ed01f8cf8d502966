"""Mesh files that cannot be used: one line naming the file and where, exit 2, no files."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import numpy as np
import pytest

from evoplan.cli import main
from evoplan.problems.toolpath.geometry.spec import parse_surface

pytest.importorskip("trimesh")

ROOT = Path(__file__).resolve().parents[3]
PART = runpy.run_path(str(ROOT / "runs" / "parts" / "make_mesh_part.py"))


def grid(f, lx=10.0, ly=8.0, s=1.0):
    xs = np.linspace(0.0, lx, int(round(lx / s)) + 1)
    ys = np.linspace(0.0, ly, int(round(ly / s)) + 1)
    X, Y = np.meshgrid(xs, ys)
    return PART["grid_triangles"](xs, ys, f(X, Y))


def stl(path: Path, triangles) -> str:
    path.write_bytes(PART["stl_bytes"](np.asarray(triangles, float)))
    return str(path)


def refused(spec, pattern):
    with pytest.raises(ValueError, match=pattern) as info:
        parse_surface(spec)
    assert "\n" not in str(info.value)
    return str(info.value)


def test_corrupt_and_empty_files_name_the_file(tmp_path):
    good = PART["stl_bytes"](grid(lambda x, y: 0.1 * x))
    cases = {"empty.stl": (b"", "the file is empty"),
             "cut.stl": (good[:-30], r"corrupt binary STL: the header announces 160 triangles \(8084 bytes\), "
                                     r"the file has 8054 bytes"),
             "short.stl": (good[:50], "corrupt binary STL: 50 bytes, shorter than its 84-byte header"),
             "text.stl": (b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
                          "corrupt ASCII STL: it ends without 'endsolid'"),
             "noise.obj": (b"this is not a mesh\n", r"holds no triangles \(empty, corrupt, or a point cloud\)"),
             "bad.ply": (b"hello\n", r"cannot read it as a PLY mesh \(Not a ply file!\)")}
    for name, (data, why) in cases.items():
        (tmp_path / name).write_bytes(data)
        refused({"type": "mesh", "file": str(tmp_path / name)}, rf"^surface.file: {tmp_path / name}: {why}")
    refused({"type": "mesh", "file": "nowhere.stl"}, r"^surface.file: file not found: nowhere.stl$")
    (tmp_path / "part.step").write_text("ISO-10303-21;")
    refused({"type": "mesh", "file": str(tmp_path / "part.step")},
            r"unsupported mesh file type '.step' \(use .stl, .obj, .ply\)")


def test_not_a_height_field_says_where(tmp_path):
    # a step: two plateaus joined by a vertical wall at x = 5
    lo, hi = grid(lambda x, y: 0 * x, lx=5.0), grid(lambda x, y: 0 * x + 2, lx=5.0) + [5.0, 0, 0]
    wall = [[[5, 0, 0], [5, 8, 0], [5, 8, 2]], [[5, 0, 0], [5, 8, 2], [5, 0, 2]]]
    msg = refused({"type": "mesh", "file": stl(tmp_path / "step.stl", np.concatenate([lo, hi, wall]))},
                  r"step.stl: not a height field over XY: vertical wall at \(x, y, z\) = \(5.00, ")
    assert "90.0 deg" in msg
    # a fold: a sheet that turns back over itself (consistently wound: one triangle faces down)
    fold = np.array([[[0, 0, 0], [4, 0, 0], [4, 4, 0]], [[0, 0, 0], [4, 4, 0], [0, 4, 0]],
                     [[4, 0, 0], [2, 0, 1], [2, 4, 1]], [[4, 0, 0], [2, 4, 1], [4, 4, 0]]])
    refused({"type": "mesh", "file": stl(tmp_path / "fold.stl", fold)},
            r"fold.stl: not a height field over XY: overhang at \(x, y, z\) = \(\d.*\(triangle \d faces down\)")
    # two separate sheets, one above the other (each faces up): found when sampled
    two = np.concatenate([grid(lambda x, y: 0 * x), grid(lambda x, y: 0 * x + 3, lx=4.0, ly=4.0) + [2.0, 2.0, 0]])
    refused({"type": "mesh", "file": stl(tmp_path / "two.stl", two)},
            r"two.stl: not a height field over XY: two sheets at \(x, y\) = \([2-6]\.\d\d, [2-6]\.\d\d\), "
            r"z = (0.00 and 3.00|3.00 and 0.00)$")


def test_non_manifold_and_degenerate_meshes(tmp_path):
    fin = [[[0, 0, 0], [4, 0, 0], [2, 3, 0]], [[4, 0, 0], [0, 0, 0], [2, -3, 0]],
           [[0, 0, 0], [4, 0, 0], [2, 3, 1]]]
    refused({"type": "mesh", "file": stl(tmp_path / "fin.stl", fin)},
            r"fin.stl: non-manifold: an edge of 3 triangles at \(x, y, z\) = \(2.00, 0.00, 0.00\)$")
    flat = [[[0, 0, 0], [1, 1, 1], [2, 2, 2]], [[0, 0, 0], [0, 0, 0], [1, 0, 0]]]
    refused({"type": "mesh", "file": stl(tmp_path / "line.stl", flat)},
            r"line.stl: degenerate: none of its \d triangles has an area$")
    wall = [[[0, 0, 0], [4, 0, 0], [4, 0, 3]], [[0, 0, 0], [4, 0, 3], [0, 0, 3]]]
    refused({"type": "mesh", "file": stl(tmp_path / "wall.stl", wall)},
            r"wall.stl: degenerate: every triangle stands vertical")
    # a few zero-area slivers among good triangles are dropped, and counted
    good = grid(lambda x, y: 0.1 * x)
    s = parse_surface({"type": "mesh", "file": stl(tmp_path / "slivers.stl",
                                                   np.concatenate([good, [[[1, 1, 0.1], [1, 1, 0.1], [2, 1, 0.2]]]]))})
    assert s.facts()["degenerate_dropped"] == 1 and s.facts()["triangles"] == len(good)


def test_cli_one_line_exit_2_no_folder(tmp_path, capsys, monkeypatch):
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "empty.stl").write_bytes(b"")
    run = tmp_path / "run.yaml"
    run.write_text("problem:\n  name: toolpath\n  params:\n    surface: {type: mesh, file: parts/empty.stl}\n"
                   "algorithm: {name: vega, population: 4}\ntermination: {generations: 1}\n")
    out = tmp_path / "out"
    assert main(["run", str(run), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "surface.file: parts/empty.stl: the file is empty" in err and str(run) in err
    assert not out.exists()
    # a long message is kept whole (where the wall is, and its slope)
    lo, hi = grid(lambda x, y: 0 * x, lx=5.0), grid(lambda x, y: 0 * x + 2, lx=5.0) + [5.0, 0, 0]
    wall = [[[5, 0, 0], [5, 8, 0], [5, 8, 2]], [[5, 0, 0], [5, 8, 2], [5, 0, 2]]]
    stl(tmp_path / "parts" / "empty.stl", np.concatenate([lo, hi, wall]))
    assert main(["run", str(run), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.rstrip().endswith("vertical wall at (x, y, z) = (5.00, 5.33, 0.67) "
                                                          "(triangle 160, 90.0 deg)")
    assert not out.exists()
    # the mesh extra missing: one line naming it
    stl(tmp_path / "parts" / "empty.stl", grid(lambda x, y: 0.1 * x))
    monkeypatch.setitem(sys.modules, "trimesh", None)
    assert main(["run", str(run), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and 'pip install "evoplan[mesh]"' in err
    assert not out.exists()


def test_a_fit_above_max_deviation_is_refused(tmp_path):
    f = stl(tmp_path / "wavy.stl", grid(lambda x, y: np.sin(x) * np.cos(y), s=0.5))
    refused({"type": "mesh", "file": f},
            r"wavy.stl: the fit is 0.\d+ mm off the mesh at \(x, y\) = \(\d+.\d\d, \d+.\d\d\), "
            r"above max_deviation 0.005 mm")
    s = parse_surface({"type": "mesh", "file": f, "max_deviation": 0.5})
    assert 0.005 < s.facts()["fit"]["max_deviation_mm"] <= 0.5
    refused({"type": "mesh", "file": f, "max_deviation": 0}, r"^surface.max_deviation: Input should be greater than 0")
    refused({"type": "mesh", "file": f, "colour": "red"}, r"^surface: unknown key\(s\) for a mesh surface: colour$")
