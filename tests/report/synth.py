"""Results folders for the report tests, made quickly: a real Kubota run, a real tiny study,
and toolpath / simulation / machine folders whose data files are written by the same writers
the commands use (``apt_toolpath``, the ``toolpath.npz`` / ``deviation.npz`` layouts) over a
synthetic toroidal-ish part, so no toolpath plan has to be computed here."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from evoplan.problems.toolpath.cutters import make_cutter

ROOT = Path(__file__).resolve().parents[2]


def part(u, v):
    x, y = 100 * u - 50, 80 * v - 40
    return np.stack([x, y, 10 + 8 * np.cos(x / 30) * np.cos(y / 25)], axis=-1)


def write_apt(path: Path, passes: int = 8, per_pass: int = 200, zones: int = 2, name: str = "finish") -> None:
    from evoplan.problems.toolpath.export.apt_write import apt_toolpath
    from evoplan.problems.toolpath.export.toolpath import Tool, Toolpath

    tips, axes, section, names = [], [], [], {}
    for k in range(passes):
        u = np.linspace(0, 1, per_pass)
        v = np.full(per_pass, (k + 0.5) / passes)
        p = part(u, v)
        tips.append(p)
        a = np.c_[np.full(per_pass, 0.1 * np.sin(k)), np.full(per_pass, 0.05), np.ones(per_pass)]
        axes.append(a / np.linalg.norm(a, axis=1, keepdims=True))
        section.append(np.full(per_pass, k))
        names[k] = f"ZONE {k * zones // passes} PASS {k}"
    tp = Toolpath.from_sections(name, Tool(6, make_cutter(16.0, 3.0)), np.concatenate(tips), np.concatenate(axes),
                                np.concatenate(section), feed=1000.0, section_names=names)
    path.write_bytes(apt_toolpath(tp, part="EVOPLAN TEST").encode())


@pytest.fixture(scope="session")
def synth(tmp_path_factory):
    import evoplan
    from evoplan.cli import main

    base = tmp_path_factory.mktemp("report")
    out = {}
    # a real run (Kubota, VEGA), then a toolpath run folder: the same files plus the toolpath's
    r = evoplan.minimize("kubota", "vega", termination={"generations": 15}, seed=1, population=12,
                         out=base / "run")
    out["run"] = r.out
    tp = base / "toolpath_run"
    shutil.copytree(r.out, tp)
    write_apt(tp / "toolpath.apt")
    u, v = np.meshgrid(np.linspace(0, 1, 21), np.linspace(0, 1, 21), indexing="ij")
    np.savez_compressed(tp / "toolpath.npz", cc=part(u.ravel(), v.ravel()), zone=np.zeros(441, int),
                        pass_index=np.zeros(441, int), surface=part(u, v), tolerance=0.01,
                        criteria_names=np.array(["cc_count", "machining_time", "scallop_max"]),
                        criteria_values=np.array([441.0, 3.2, 0.012]))
    front = base / "pareto_run"
    shutil.copytree(r.out, front)
    f1 = np.linspace(0, 1, 9)
    rows = ["tool,stepover,F_machining_error,F_machining_time,weighted_sum,weighted_choice,machining_time"]
    rows += [f"6,{30 + i},{a:.4f},{(1 - a) ** 2:.4f},{0.5 * a + 0.5 * (1 - a) ** 2:.4f},{i == 5},{3 + a:.3f}"
             for i, a in enumerate(f1)]
    (front / "pareto.csv").write_text("\n".join(rows) + "\n")
    out["toolpath_run"], out["pareto_run"] = tp, front
    # a real tiny study
    study = base / "study.yaml"
    study.write_text("name: tiny\nseed: 7\nseeds: 3\nbudget: {evaluations: 120}\nproblems:\n  - {name: kubota}\n"
                     "  - {name: rastrigin, dimensions: [2]}\nalgorithms:\n  - {name: ga, population: 10}\n"
                     "  - {name: vega, population: 10, virus: {count: 3}}\n  - {name: pymoo_de, pop_size: 10}\n"
                     "statistics: {reference: ga, test: signed_rank, alpha: 0.05}\n"
                     "output: {plots: false}\n")  # the report draws its own figures: the PNGs cost 9 s
    assert main(["study", str(study), "--out", str(base / "study"), "--quiet"]) == 0
    out["study"] = base / "study"
    # a simulation folder (simulation.json + deviation.npz, the layout evoplan simulate writes)
    sim = base / "simulation"
    sim.mkdir()
    h, ny, nx = 0.5, 160, 200
    ys, xs = np.mgrid[0:ny, 0:nx] * h
    res = 0.02 * np.sin(xs / 3.0) - 0.004
    res[40:44, 50:60] = 0.8  # uncut (above the allowance)
    (sim / "simulation.json").write_text(json.dumps({"plan": "synthetic", "scallop_max_mm": 0.016,
                                                     "gouge_max_mm": 0.024, "grid_mm": h}))
    np.savez_compressed(sim / "deviation.npz", x0=0.0, y0=0.0, h=h, z=(5 + 0.05 * xs).astype(np.float32),
                        inside=np.ones((ny, nx), bool), residual=res.astype(np.float32),
                        labels=np.zeros((ny, nx), np.int16), tolerance=0.01, allowance=0.5,
                        tip=np.zeros((2, 3)), axis=np.tile([0, 0, 1.0], (2, 1)), section=np.zeros(2, int),
                        zone=np.zeros(2, int))
    out["simulation"] = sim
    # a machine folder: summary.json and an operation's APT file
    mach = base / "machine"
    mach.mkdir()
    write_apt(mach / "finish.apt", passes=12, per_pass=150, zones=1)
    (mach / "summary.json").write_text(json.dumps({"name": "synthetic", "post": "fanuc", "finish": {
        "tool": {"number": 3, "label": "toroidal D16 r3"}, "points": 1800, "lengths_mm": {"cutting": 1200.0},
        "time_min": 1.2, "nc_bytes": 50000, "nc_lines": 1900, "multi_axis": True}}))
    out["machine"] = mach
    return out
