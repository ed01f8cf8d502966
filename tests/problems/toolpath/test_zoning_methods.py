"""Zoning-method registry and the zone merging post-process (zoning/methods/, zoning/merge.py)."""

import json
from pathlib import Path

import numpy as np
import pytest
from pydantic import Field
from scipy import ndimage

from evoplan.cli import main as cli_main
from evoplan.problems.toolpath import choi_surface
from evoplan.problems.toolpath.plan.zoning.features import MeshFeatures, mesh_features
from evoplan.problems.toolpath.plan.zoning.kmeans import connected_zones
from evoplan.problems.toolpath.plan.zoning.merge import (MergeSettings, merge_by_length,
                                                    merge_small_zones)
from evoplan.problems.toolpath.plan.zoning.methods import (REGISTRY, ZoningMethod, ZoningSettings,
                                                      register, unregister)
from evoplan.problems.toolpath.plan.zoning.plan import plan_zones
from evoplan.problems.toolpath import ToolpathProblem
from tests.choi_zoning import choi_zoning
from evoplan.problems.toolpath.plan.zoning.samples import sample_surface
from evoplan.problems.toolpath.plan.zoning.stepover import ScallopTarget

from test_zoning import TORUS, TwoPlanes

RUNS = Path(__file__).resolve().parents[3] / "runs"


class StripSettings(ZoningSettings):
    strips: int = Field(2, ge=1)


class Strips(ZoningMethod):
    """Equal strips along u (a method defined by a test, not by evoplan)."""

    name = "strips_test"
    Settings = StripSettings

    def labels(self, features, settings, seed=0):
        n, m = features.shape
        return (np.arange(n)[:, None] * settings.strips // n + np.zeros((1, m), int)), {}


@pytest.fixture
def strips():
    method = register(Strips)
    yield method
    unregister(method.name)


def assert_connected(labels):
    ids = np.unique(labels)
    np.testing.assert_array_equal(ids, np.arange(ids.size))
    for z in ids:
        assert ndimage.label(labels == z)[1] == 1, f"zone {z} is not 4-connected"


def test_builtin_methods_are_registered_with_their_settings():
    assert list(REGISTRY)[:3] == ["single", "kmeans", "amas"]
    assert REGISTRY["kmeans"].settings({"K": 4}).K == 4
    assert REGISTRY["amas"].settings().k_lz == 0.15
    with pytest.raises(ValueError, match=r"^amas\.k_lz: must be in \[0, 1\]"):
        REGISTRY["amas"].settings({"k_lz": 2})
    with pytest.raises(ValueError, match=r"^kmeans\.bogus: Extra inputs"):
        REGISTRY["kmeans"].settings({"bogus": 1})
    with pytest.raises(ValueError, match="already registered"):
        register(type("Again", (Strips,), {"name": "kmeans"}))


def test_a_method_registered_in_a_test_plans_and_runs_the_command(strips, tmp_path):
    surface = TwoPlanes()
    plan = plan_zones(surface, TORUS, "strips_test", mesh=(12, 9), merge=None, strips=3)
    assert plan.method == "strips_test" and len(plan.zones) == 3
    with pytest.raises(ValueError, match=r"^strips_test\.strips: Input should be greater"):
        plan_zones(surface, TORUS, "strips_test", mesh=(12, 9), strips=0)
    # the zone command knows it without any change to evoplan/commands/zone.py
    cfg = tmp_path / "z.yaml"
    cfg.write_text("surface: choi\nmesh: [12, 12]\nmethod: strips_test\n"
                   "strips_test: {strips: 4}\nmerge: {min_zone_area: 0, by_length: false}\n"
                   "sample_spacing: 1.0\ndirection_scan: 2\n")
    assert cli_main(["zone", str(cfg), "--out", str(tmp_path / "out")]) == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["method"] == "strips_test" and summary["n_zones"] == 4
    cfg.write_text("surface: choi\nmesh: [12, 12]\nmethod: strips_test\nstrips_test: {strips: -1}\n")
    assert cli_main(["zone", str(cfg), "--out", str(tmp_path / "bad")]) == 2
    assert not (tmp_path / "bad").exists()
    # and the toolpath problem refuses it as a gene source: it declares no gene
    with pytest.raises(ValueError, match=r"^ranges.zones: not a gene of this configuration"):
        ToolpathProblem(**choi_zoning(mesh=(6, 6), method="strips_test", ranges={"zones": [1, 3]}))


def test_unknown_method_lists_the_registered_ones(strips, tmp_path, capsys):
    cfg = tmp_path / "z.yaml"
    cfg.write_text("surface: choi\nmethod: nope\n")
    assert cli_main(["zone", str(cfg), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "method: expected one of single, kmeans, amas, strips_test" in err
    with pytest.raises(ValueError, match="^method: expected one of"):
        plan_zones(TwoPlanes(), TORUS, "nope", mesh=(6, 6))


def toy_features(direction, slope_deg=10.0):
    """Unit-area cells with the given direction field (radians) and one slope."""
    d = np.asarray(direction, float)
    n, m = d.shape
    u, v = np.meshgrid((np.arange(n) + 0.5) / n, (np.arange(m) + 0.5) / m, indexing="ij")
    s = np.full(d.shape, np.radians(slope_deg))
    return MeshFeatures(u, v, s, d, d, np.ones(d.shape))


def test_a_small_zone_joins_the_neighbour_of_closest_direction():
    d = np.zeros((9, 6))
    d[:4] = np.radians(90)          # zone 0: 90 deg
    d[4] = np.radians(10)           # zone 1, one row (6 of 54 cells): 10 deg
    labels = np.repeat([0, 0, 0, 0, 1, 2, 2, 2, 2], 6).reshape(9, 6)  # zone 2: 0 deg
    f = toy_features(d)
    out = merge_small_zones(labels, f, min_fraction=0.2)
    assert len(np.unique(out)) == 2
    assert np.all(out[4] == out[5]) and np.all(out[4] != out[3])  # joined the 0-deg zone
    d[4] = np.radians(80)
    out = merge_small_zones(labels, toy_features(d), min_fraction=0.2)
    assert np.all(out[4] == out[3]) and np.all(out[4] != out[5])  # now the 90-deg zone


def test_no_zone_under_the_minimum_area_and_zones_stay_connected():
    f = mesh_features(choi_surface(), 30, 30)
    rng = np.random.default_rng(3)
    labels = connected_zones(rng.integers(0, 4, size=(30, 30)))  # hundreds of tiny zones
    assert labels.max() > 100
    for frac in (0.01, 0.05, 0.2):
        out = merge_small_zones(labels, f, frac)
        area = np.bincount(out.ravel(), f.area.ravel())
        assert area.min() >= frac * f.area.sum() and out.max() >= 1
        assert_connected(out)
        # a merge never splits a zone: every old zone lies inside one new zone
        assert all(len(np.unique(out[labels == z])) == 1 for z in range(labels.max() + 1))


def test_length_merging_stops_when_no_merge_pays_its_delta_l():
    kind = np.repeat([0, 0, 1, 1], 5)[:, None] * np.ones((1, 4), int)  # two kinds, four zones
    labels = np.repeat([0, 1, 2, 3], 5)[:, None] * np.ones((1, 4), int)

    def length(mask):  # one mm per cell, plus 100 mm for each extra kind in the zone
        return mask.sum() + 100.0 * (len(np.unique(kind[mask])) - 1)

    out, evaluations = merge_by_length(labels, length, delta_l=40.0)
    np.testing.assert_array_equal(out, kind)  # 0+1 and 2+3 merged (saves 40), kinds kept apart
    assert evaluations >= 4
    out, _ = merge_by_length(labels, length, delta_l=150.0)  # a slow zone change: one zone
    assert np.all(out == 0)
    out, _ = merge_by_length(labels, length, delta_l=0.0)  # free changes: nothing merged
    np.testing.assert_array_equal(out, labels)


@pytest.mark.parametrize("method", ["kmeans", "amas"])
def test_two_planes_keep_two_zones_through_the_default_merging(method):
    surface = TwoPlanes()
    settings = {"K": 2} if method == "kmeans" else {}
    samples = sample_surface(surface)
    plan = plan_zones(surface, TORUS, method, mesh=(24, 18), samples=samples,
                      merge=MergeSettings(min_zone_area=0.2), **settings)
    half = (plan.features.u < 0.5).astype(int)
    assert np.all(plan.labels == half) or np.all(plan.labels == 1 - half)
    assert sorted(round(z.direction_deg) % 180 for z in plan.zones) == [0, 90]
    # Delta L above what the second direction saves: the planes are machined as one zone
    plan = plan_zones(surface, TORUS, method, mesh=(24, 18), samples=samples, delta_l=1e4,
                      **settings)
    assert len(plan.zones) == 1


def test_shipped_amas_default_on_choi_beats_raw_amas_and_a_single_zone():
    """Through the one engine: the lengths are those of the sections cut."""
    from dataclasses import replace

    from evoplan.commands.zone import build_plan, load, summary
    from evoplan.problems.toolpath.plan.planner import Planner

    cfg = load(str(RUNS / "choi_zoning.yaml"))
    assert cfg.method == "amas" and cfg.merge == MergeSettings()
    surface, planner, genes, batch, seconds = build_plan(cfg, RUNS)
    facts = summary(cfg, planner, genes, batch, seconds)

    def total(spec, g):
        other = Planner(surface, planner.tools, machine="3axis", zoning=spec,
                        spacing="scallop", h_c=cfg.h_c, feed_angle=None)
        b = other.plan(g, place=False)
        return float(b.seg_len.sum()) + (int(b.zones[0]) - 1) * cfg.delta_l, other, b

    spec = planner.layouts.spec
    raw_total, raw_planner, raw = total(replace(spec, merge=None), genes)
    single_total, _, _ = total(replace(spec, method="single", settings={}),
                               {k: genes[k] for k in ("tool", "step")})
    assert facts["info"]["merge"]["zones_in"] == int(raw.zones[0]) > 10  # AMAS alone fragments
    assert facts["n_zones"] < int(raw.zones[0])
    assert facts["total_length_mm"] < single_total < raw_total
    labels = planner.layout(genes).labels
    assert_connected(labels)
    area = np.array([z["area_mm2"] for z in facts["zones"]])
    assert area.min() >= cfg.merge.min_zone_area * area.sum()
