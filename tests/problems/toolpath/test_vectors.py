"""``geometry/vectors.py`` gives numpy's general routines' numbers bit for bit: row norms as
``np.linalg.norm(axis=-1)``, cross products as ``np.cross``, row gathers as fancy indexing;
on values of every magnitude, zeros of both signs, infinities and NaN. ``rows.present``
gives ``np.unique``'s labels."""

import numpy as np
import pytest

from evoplan.problems.toolpath.geometry.vectors import cross_rows, row_norms, take_rows


def same_bits(a, b) -> bool:
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(
        a.view(np.uint64), b.view(np.uint64))


def awkward(shape, seed):
    """Standard normals scaled over 10^-160 .. 10^160, with signed zeros, inf and NaN."""
    rng = np.random.default_rng(seed)
    a = rng.standard_normal(shape) * 10.0 ** rng.integers(-160, 160, shape)
    flat = a.reshape(-1)
    flat[::17], flat[3::19], flat[5::23], flat[7::29] = 0.0, -0.0, np.inf, np.nan
    flat[11::31] = -np.inf
    return a


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # inf - inf, overflow
@pytest.mark.parametrize("width", [2, 3])
def test_row_norms_are_numpys_norms(width):
    a = awkward((5000, width), width)
    assert same_bits(row_norms(a), np.linalg.norm(a, axis=-1))
    view = awkward((18, 3000), 9).T.reshape(3000, 6, 3)[:, 2, :width]  # a jet field's layout
    assert same_bits(row_norms(view), np.linalg.norm(view, axis=-1))
    assert same_bits(row_norms(a[None]), np.linalg.norm(a[None], axis=-1))  # leading axes


def test_row_norms_of_other_widths_fall_back_to_numpy():
    a = awkward((100, 5), 4)
    with np.errstate(all="ignore"):
        assert same_bits(row_norms(a), np.linalg.norm(a, axis=-1))


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_cross_rows_is_numpys_cross_with_broadcasting():
    a, b = awkward((4000, 3), 1), awkward((4000, 3), 2)
    assert same_bits(cross_rows(a, b), np.cross(a, b))
    c = np.array([-0.3, 0.95, 0.0])
    assert same_bits(cross_rows(c, b), np.cross(c, b))
    assert same_bits(cross_rows(b, c[None]), np.cross(b, c[None]))


def test_take_rows_is_fancy_indexing():
    rng = np.random.default_rng(3)
    a = awkward((1000, 3), 5)
    idx = rng.integers(0, 1000, 2500)
    assert same_bits(take_rows(a, idx), a[idx])
    assert same_bits(take_rows(a[:, 0], idx), a[:, 0][idx])
    flags = rng.random(1000) < 0.5
    assert np.array_equal(take_rows(flags, idx), flags[idx])
    assert take_rows(a, np.zeros(0, int)).shape == (0, 3)
    with pytest.raises(IndexError):
        take_rows(a, np.array([1000]))


def test_present_labels_are_np_unique():
    from evoplan.problems.toolpath.geometry.rows import present

    rng = np.random.default_rng(4)
    for labels in (rng.integers(0, 9, 5000), np.array([3, 3, 3]), np.zeros(0, int),
                   rng.integers(0, 2, (40, 3))):
        assert np.array_equal(present(labels), np.unique(labels))
    with pytest.raises(ValueError):
        present(np.array([-1, 2]))
