"""AMAS zoning (Djebali et al. Sec. 5): zones, connectivity, determinism, symmetry, errors."""

import numpy as np
import pytest
from scipy import ndimage

from evoplan.problems.toolpath.plan.zoning.amas import AmasResult, amas_zoning, simple_point_lut

SEEDS = range(4)


def smooth_field(n, m):
    """Steepest-slope direction of z = sin(3u) cos(2v) on [0, 1]^2."""
    u = np.linspace(0, 1, n)[:, None]
    v = np.linspace(0, 1, m)[None, :]
    return np.arctan2(-2 * np.sin(3 * u) * np.sin(2 * v), 3 * np.cos(3 * u) * np.cos(2 * v))


def noise_field(n, m, seed=7):
    return np.random.default_rng(seed).uniform(-np.pi, np.pi, (n, m))


def half_planes(n=12, m=10):
    d = np.zeros((n, m))
    d[n // 2:] = np.pi / 2
    return d


def n_zones(res):
    return int(res.labels.max()) + 1


def assert_valid_labels(labels):
    labels = np.asarray(labels)
    assert labels.dtype == np.int64
    ids, first = np.unique(labels.ravel(), return_index=True)
    np.testing.assert_array_equal(ids, np.arange(ids.size))  # contiguous 0..Z-1
    assert np.all(np.diff(first) > 0)  # numbered in first-occurrence order of a C-order scan
    for z in ids:
        assert ndimage.label(labels == z)[1] == 1, f"zone {z} is not 4-connected"


@pytest.mark.parametrize("seed", SEEDS)
def test_two_half_planes_give_exactly_the_two_halves(seed):
    d = half_planes()
    res = amas_zoning(d, k_cmd=1.0, k_lz=0.15, seed=seed)
    assert isinstance(res, AmasResult) and res.settled
    expected = (np.arange(12) >= 6).astype(np.int64)[:, None] * np.ones(10, np.int64)
    np.testing.assert_array_equal(res.labels, expected)


@pytest.mark.parametrize("seed", SEEDS)
def test_constant_direction_gives_a_single_zone(seed):
    res = amas_zoning(np.full((15, 11), 0.7), seed=seed)
    assert res.settled and n_zones(res) == 1 and res.actions > 0


@pytest.mark.parametrize("aggregate", ["mean", "leximin"])
@pytest.mark.parametrize("satisfaction", ["weighted", "printed"])
@pytest.mark.parametrize("field", [smooth_field(24, 18), noise_field(16, 20)],
                         ids=["smooth", "noise"])
def test_zones_are_4_connected_and_labels_contiguous(field, satisfaction, aggregate):
    for seed in SEEDS:
        res = amas_zoning(field, k_lz=0.2, seed=seed, satisfaction=satisfaction,
                          aggregate=aggregate)
        assert res.labels.shape == field.shape
        assert_valid_labels(res.labels)


def test_connectivity_with_neutral_meshes():
    neutral = np.random.default_rng(3).random((20, 20)) < 0.3
    for seed in SEEDS:
        assert_valid_labels(amas_zoning(noise_field(20, 20), seed=seed, neutral=neutral).labels)


@pytest.mark.parametrize("field", [smooth_field(30, 25), noise_field(15, 15)],
                         ids=["smooth", "noise"])
def test_same_seed_same_result_and_settled(field):
    a = amas_zoning(field, seed=11)
    b = amas_zoning(field, seed=11)
    np.testing.assert_array_equal(a.labels, b.labels)
    assert (a.cycles, a.actions, a.settled) == (b.cycles, b.actions, True)


def test_directions_are_axial():
    for field in (smooth_field(30, 25), noise_field(18, 18)):
        for seed in SEEDS:
            ref = amas_zoning(field, seed=seed).labels
            for shift in (np.pi, -np.pi, 3 * np.pi):
                np.testing.assert_array_equal(amas_zoning(field + shift, seed=seed).labels, ref)


def test_larger_k_lz_gives_no_more_zones():
    field = smooth_field(30, 25)
    for seed in SEEDS:
        counts = [n_zones(amas_zoning(field, k_lz=k, seed=seed)) for k in (0.05, 0.15, 0.35)]
        assert counts[0] >= counts[1] >= counts[2] >= 1, counts
        assert counts[0] > counts[2]


def test_weighted_zones_stop_growing_near_k_lz_pi_sector():
    field = np.mod(smooth_field(40, 40), np.pi)
    for k_lz in (0.15, 0.35):
        labels = amas_zoning(field, k_lz=k_lz).labels
        for z in range(labels.max() + 1):
            x = np.sort(field[labels == z])
            gap = max(x[0] + np.pi - x[-1], np.diff(x).max(initial=0.0))
            assert np.pi - gap < 1.1 * k_lz * np.pi  # sector gamma of the zone


def test_all_neutral_meshes_make_one_zone():
    res = amas_zoning(noise_field(12, 12), neutral=np.ones((12, 12), bool))
    assert res.settled and n_zones(res) == 1


def test_neutral_meshes_do_not_split_a_zone():
    d = np.full((14, 10), 0.3)
    neutral = np.zeros_like(d, bool)
    neutral[5:9] = True
    d[neutral] = noise_field(4, 10).ravel()
    assert n_zones(amas_zoning(d, neutral=neutral)) == 1
    assert n_zones(amas_zoning(d)) > 1  # the same directions counted split it


def test_leximin_cannot_merge_zones_of_several_meshes():
    # documented limit of a min-first situation order: a constant field stays fragmented
    res = amas_zoning(np.zeros((12, 12)), aggregate="leximin")
    assert res.settled and n_zones(res) > 1
    assert np.bincount(res.labels.ravel()).max() < 12 * 12


@pytest.mark.parametrize("k_lz", [0.15, 0.35])
def test_printed_satisfaction_runs(k_lz):
    res = amas_zoning(smooth_field(30, 25), k_lz=k_lz, satisfaction="printed")
    assert res.settled and 1 <= n_zones(res) < 30 * 25
    assert_valid_labels(res.labels)


def test_max_cycles_reached_is_not_an_error():
    res = amas_zoning(smooth_field(30, 25), max_cycles=1)
    assert (res.cycles, res.settled) == (1, False) and res.actions > 0
    assert_valid_labels(res.labels)


def test_labels_are_read_only():
    res = amas_zoning(np.zeros((3, 4)))
    with pytest.raises(ValueError):
        res.labels[0, 0] = 5


def test_simple_point_table():
    lut = simple_point_lut()
    n, ne, e, se, s, sw, w, nw = (1 << r for r in range(8))
    assert lut[0] and lut[255] and lut[n] and lut[n | ne | e] and lut[n | ne | e | se | s]
    assert not lut[n | s] and not lut[n | e] and not lut[e | w | ne | nw]
    assert lut[n | e | s | w | ne | se | sw] and not lut[n | e | s | w | ne | sw]


@pytest.mark.parametrize("kwargs, key", [
    (dict(k_cmd=-0.1), "k_cmd"),
    (dict(k_cmd="a"), "k_cmd"),
    (dict(k_lz=1.5), "k_lz"),
    (dict(direction=np.zeros((1, 1))), "direction"),
    (dict(direction=np.zeros((0, 0))), "direction"),
    (dict(direction=np.zeros(5)), "direction"),
    (dict(direction=np.array([[0.0, np.nan]])), "direction"),
    (dict(satisfaction="best"), "satisfaction"),
    (dict(aggregate="max"), "aggregate"),
    (dict(max_cycles=0), "max_cycles"),
    (dict(max_cycles=2.5), "max_cycles"),
    (dict(neutral=np.zeros((2, 2), bool)), "neutral"),
])
def test_bad_input_raises_value_error_naming_the_parameter(kwargs, key):
    kwargs = {"direction": np.zeros((3, 3)), **kwargs}
    with pytest.raises(ValueError, match=f"^{key}: ") as err:
        amas_zoning(**kwargs)
    assert "\n" not in str(err.value)
