"""Threads in the cut simulation: the tiles shared among threads give the single-threaded
residual bit for bit; ``simulation.threads`` is refused beside a parallel evaluation backend."""

import numpy as np
import pytest

from evoplan.config import parse_config
from evoplan.errors import ConfigError
from evoplan.problems.toolpath.problem import ToolpathProblem
from evoplan.problems.toolpath.simulation import design_grid, sweep_path
from evoplan.problems.toolpath.simulation.sweep import _only, tile_groups
from evoplan.runner import prepare

VEGA = dict(tool=6, stepover=41.729, lead=2.957, tilt=0.027, step=6.338)
NORM = {"machining_error": [0, 0.5], "cc_count": [0, 1000]}


@pytest.mark.parametrize("threads", [2, 3])
def test_threaded_sweep_equals_the_single_threaded_one_bit_for_bit(threads):
    pr = ToolpathProblem(normalization=NORM)
    path, _ = pr.cl_path(VEGA)
    grid = design_grid(pr.surface, 0.8)
    one = sweep_path(path, grid)
    many = sweep_path(path, grid, threads=threads)
    assert np.isfinite(one.values[grid.inside]).all()
    assert np.array_equal(one.values, many.values, equal_nan=True)
    assert one.work == many.work  # the same entries computed, only by other threads


def test_tile_groups_cover_every_tile_with_moves_once():
    ptr = np.array([0, 3, 3, 7, 8, 8, 12])
    moves = np.arange(12) * 10
    groups = tile_groups(ptr, 2)
    assert sorted(np.concatenate(groups).tolist()) == [0, 2, 3, 5]
    listed = []
    for g in groups:
        sub, mv = _only(ptr, moves, g)
        assert sub[-1] == len(mv) and (np.diff(sub)[np.setdiff1d(np.arange(6), g)] == 0).all()
        listed += mv.tolist()
    assert sorted(listed) == moves.tolist()


def test_threads_need_the_serial_backend_and_a_whole_number():
    run = {"problem": {"name": "toolpath", "params": {"criteria": "simulated", "normalization": NORM,
                                                       "simulation": {"threads": 2}}},
           "algorithm": {"name": "ga", "population": 4}, "termination": {"generations": 1},
           "evaluation": {"backend": "processes", "workers": 2}}
    with pytest.raises(ConfigError, match="simulation.threads: 2 threads need evaluation.backend: serial"):
        prepare(parse_config(run), "run.yaml")
    bad = {**run, "evaluation": {"backend": "serial"}}
    bad["problem"] = {"name": "toolpath", "params": {"criteria": "simulated", "normalization": NORM,
                                                      "simulation": {"threads": 0}}}
    with pytest.raises(ConfigError, match="simulation.threads: expected a whole number"):
        prepare(parse_config(bad), "run.yaml")
