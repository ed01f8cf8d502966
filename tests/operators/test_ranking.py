"""The population's order: the compiled radix sort against numpy's stable sort."""

import numpy as np
import pytest

from evoplan import compiled
from evoplan.operators import ranking
from evoplan.operators.ranking_kernels import radix_order


def _values(rng, n, kind):
    if kind == "normal":
        return rng.normal(size=n)
    if kind == "ties":
        return np.round(rng.normal(size=n), 1)
    if kind == "specials":  # signed zeros, subnormals, the ends of the range, failures
        return rng.choice([0.0, -0.0, 1.0, -1.0, 5e-324, -5e-324, 1e308, -1e308, np.inf, -np.inf, np.nan], size=n)
    if kind == "converged":  # the high digits shared: passes skipped
        return np.round(rng.random(n) * 1e-3 + 0.147, 6)
    return rng.normal(size=n) * 10.0 ** rng.integers(-300, 300, n)  # every exponent


@pytest.mark.parametrize("kind", ["normal", "ties", "specials", "converged", "scales"])
@pytest.mark.parametrize("n", [0, 1, 2, 37, 511, 512, 2000, 5003])
def test_radix_order_is_numpys_stable_sort_with_nan_last(kind, n):
    rng = np.random.default_rng(n)
    for _ in range(5):
        f = _values(rng, n, kind)
        expected = np.argsort(np.where(np.isnan(f), np.inf, f), kind="stable")
        assert np.array_equal(radix_order(f), expected)
        for mode in ("never", "always"):
            with compiled.forced(mode):
                assert np.array_equal(ranking.stable_order(f), expected)
