import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from evoplan.space import Categorical, Integer, Real, Space, binary_to_gray, gray_to_binary


def bits(s: str) -> np.ndarray:
    return np.array([[c == "1" for c in s]])


def test_eq8_on_known_bit_strings():
    space = Space([Real("x", -1.0, 1.0, 23), Real("y", 2.0, 9.0, 3)])
    ones, zeros = "1" * 23, "0" * 23
    np.testing.assert_allclose(space.decode(bits(zeros + "000"))[0], [-1.0, 2.0])
    np.testing.assert_allclose(space.decode(bits(ones + "111"))[0], [1.0, 9.0])
    # '101' = 5 -> 2 + 5 * 7 / 7 = 7 ; MSB only -> -1 + 2**22 * 2 / (2**23 - 1)
    x = space.decode(bits("1" + "0" * 22 + "101"))[0]
    assert x[1] == pytest.approx(7.0)
    assert x[0] == pytest.approx(-1 + 2**22 * 2 / (2**23 - 1), abs=1e-15)


def test_fountas_46_bit_chromosome():
    space = Space([Real("x", -1, 1, 23), Real("y", -1, 1, 23)])
    assert space.n_bits == 46
    assert space.decode(np.zeros((1, 46), bool)).shape == (1, 2)


def test_gray_code_known_values():
    # Gray 110 -> binary 100 (4); 3 bits on [0, 7] so the value is the integer itself
    space = Space([Real("x", 0, 7, 3)], gray=True)
    assert space.decode(bits("110"))[0, 0] == pytest.approx(4.0)
    assert space.decode(bits("010"))[0, 0] == pytest.approx(3.0)
    # neighbouring integers differ by one bit in Gray code
    G = space.encode(np.arange(8.0)[:, None])
    assert (np.sum(G[1:] != G[:-1], axis=1) == 1).all()


@given(st.lists(st.booleans(), min_size=1, max_size=40))
def test_gray_roundtrip(row):
    B = np.array([row])
    assert np.array_equal(gray_to_binary(binary_to_gray(B)), B)


def test_integer_and_categorical_bins_are_uniform():
    space = Space([Integer("k", 3, 6, 4), Categorical("tool", ("flat", "ball", "torus", "x"), 4)])
    codes = ((np.arange(16)[:, None] >> np.arange(3, -1, -1)) & 1).astype(bool)
    X = space.decode(np.hstack([codes, codes]))
    assert np.bincount(X[:, 0].astype(int) - 3).tolist() == [4, 4, 4, 4]
    assert np.bincount(X[:, 1].astype(int)).tolist() == [4, 4, 4, 4]
    assert space.named(X[-1]) == {"k": 6, "tool": "x"}


@settings(max_examples=60, deadline=None)
@given(
    st.integers(1, 30), st.integers(1, 30), st.booleans(),
    st.lists(st.booleans(), min_size=60, max_size=60),
)
def test_decode_encode_roundtrip(b1, b2, gray, flat):
    space = Space([Real("a", -3.5, 10.0, b1), Integer("k", -2, 5), Real("c", 0.0, 1e-3, b2),
                   Categorical("t", tuple("abcde"))], gray=gray)
    G = np.array(flat[: space.n_bits] + [False] * max(0, space.n_bits - 60))[None, :space.n_bits]
    X = space.decode(G)
    # decoding the encoding of a decoded point gives the point back, and reals hit the same code
    np.testing.assert_allclose(space.decode(space.encode(X)), X, rtol=0, atol=1e-12)
    real = np.r_[space.offsets[0]:space.offsets[1]]
    assert np.array_equal(space.encode(X)[:, real], G[:, real])
    assert (X[:, 0] >= -3.5).all() and (X[:, 0] <= 10).all()


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Real("x", 1.0, 1.0), "below"),
        (lambda: Real("x", 0, 1, 0), "bits"),
        (lambda: Real("x", 0, 1, 60), "bits"),
        (lambda: Integer("k", 0, 9, 3), "cannot code"),
        (lambda: Categorical("t", ("a",)), "2 choices"),
        (lambda: Space([Real("x", 0, 1), Real("x", 0, 2)]), "unique"),
    ],
)
def test_bad_variables_raise(make, match):
    with pytest.raises(ValueError, match=match):
        make()
