"""When the core takes its compiled kernels: the rule, and a small run that never loads numba."""

import subprocess
import sys

import pytest

from evoplan import compiled


@pytest.fixture
def auto(monkeypatch):
    """The auto rule from a fresh count, in a process without numba loaded."""
    monkeypatch.setattr(compiled, "_mode", "auto")
    monkeypatch.setattr(compiled, "_rows", 0)
    monkeypatch.delitem(sys.modules, "numba", raising=False)


def test_numpy_until_the_process_has_put_the_break_even_rows_through(auto):
    assert not compiled.use_compiled(compiled.SWITCH_ROWS - 1)
    assert not compiled.use_compiled()  # a look without rows counts nothing
    assert compiled.use_compiled(1)
    assert compiled.use_compiled()  # and stays compiled


def test_compiled_at_once_when_numba_is_loaded_already(auto, monkeypatch):
    monkeypatch.setitem(sys.modules, "numba", object())
    assert compiled.use_compiled(1)


def test_a_fixed_mode_holds_and_a_bad_one_is_refused(auto):
    assert compiled.set_mode("always") == "auto"
    assert compiled.use_compiled()
    compiled.set_mode("never")
    assert not compiled.use_compiled(10 * compiled.SWITCH_ROWS)
    with pytest.raises(ValueError, match="compiled mode: expected one of auto, always, never"):
        compiled.set_mode("sometimes")


@pytest.mark.parametrize("algorithm", ["ga", "vega"])
def test_a_small_run_never_loads_numba(algorithm):
    code = ("import sys, evoplan; "
            f"r = evoplan.minimize('kubota', '{algorithm}', {{'generations': 20}}, pop_size=50); "
            "print(r.evaluations > 0, 'numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", "False"], (out.stdout, out.stderr[-2000:])


def test_forced_holds_a_mode_for_a_block_and_restores_the_previous_one(auto):
    with compiled.forced("never"):
        assert not compiled.use_compiled(10 * compiled.SWITCH_ROWS)
        with pytest.raises(RuntimeError):
            with compiled.forced("always"):
                assert compiled.use_compiled()
                raise RuntimeError("inside")
        assert not compiled.use_compiled()  # restored after the inner block, even on an error
    assert compiled.set_mode("auto") == "auto"


def test_the_one_pass_breeding_leaves_the_count_to_the_path_it_falls_back_to(auto):
    """Before the switch the GA breeds by the operators one by one, and ``breed`` counts the
    children: the one-pass form, stepping aside, must not count them a second time."""
    import numpy as np

    from evoplan.operators import breeding

    G = np.random.default_rng(0).random((20, 8)) < 0.5
    f = np.arange(20.0)
    assert breeding.breed_ranked_single_point(G, f, np.argsort(f, kind="stable"), 2.0, 0.9, 0.5, 19,
                                              np.random.default_rng(1)) is None
    assert compiled._rows == 0
