"""Best-so-far on a grid, fixed-target runtimes (exact at the budget) and ECDFs."""

from __future__ import annotations

import numpy as np
import pandas as pd

from evoplan.study.curves import best_on_grid, ecdf, reference_values, runtimes

HISTORY = pd.DataFrame({"evaluations": [20, 40, 60], "best": [5.0, 1.0, 0.5]})


def test_best_so_far_is_a_step_function_of_evaluations():
    out = best_on_grid(HISTORY, np.array([1, 20, 39, 40, 100]))
    assert np.isnan(out[0]) and out[1:].tolist() == [5.0, 5.0, 1.0, 0.5]


def test_runtime_is_the_first_generation_reaching_the_target():
    t = runtimes(HISTORY, final_best=0.5, budget=None, absolute_targets=np.array([10.0, 1.0, 0.7, 0.1]))
    assert t.tolist() == [20.0, 40.0, 60.0, np.inf]


def test_runtime_respects_the_exact_budget():
    # budget 50: the last generation crossed it; the in-budget best was 0.8 (final_best)
    t = runtimes(HISTORY, final_best=0.8, budget=50, absolute_targets=np.array([1.0, 0.8, 0.5]))
    assert t.tolist() == [40.0, 50.0, np.inf]


def test_ecdf_counts_run_target_pairs():
    times = np.array([[10.0, np.inf], [30.0, 30.0]])
    assert ecdf(times, np.array([5, 10, 30, 1e9])).tolist() == [0.0, 0.25, 0.75, 0.75]


def test_reference_value_is_the_known_optimum_else_the_best_found():
    runs = pd.DataFrame({"problem": ["a", "a", "b", "b"], "dimension": [2, 2, 2, 2],
                         "optimum": [0.0, 0.0, np.nan, np.nan], "final_best": [1.0, 2.0, 3.0, -4.0]})
    assert reference_values(runs).to_dict() == {("a", 2): 0.0, ("b", 2): -4.0}
