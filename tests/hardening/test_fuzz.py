"""Fuzzing the edge: hypothesis mutates config trees and raw file bytes.

Whatever the input, reading and preparing a run either succeeds or raises one
:class:`~evoplan.errors.EvoplanError` whose message is one short line: never another
exception (a traceback for a user) and never an echo of a huge input.
"""

from __future__ import annotations

import math

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from evoplan.commands.run import load
from evoplan.errors import EvoplanError
from evoplan.runner import prepare
from evoplan.safe_yaml import load_text

BASE = {
    "seed": 1,
    "problem": {"name": "kubota", "bits": 12, "params": {}, "variables": {}},
    "algorithm": {"name": "vega", "population": 8, "elitism": 1, "fitness": {"normalize": "rank", "pressure": 2.0},
                  "selection": {"kind": "roulette"}, "crossover": {"kind": "single_point", "rate": 0.9},
                  "mutation": {"kind": "single_point", "rate": 0.5},
                  "virus": {"count": 3, "max_length": 8, "infection_rate": 0.7}},
    "termination": {"generations": 2, "evaluations": None, "target": None, "seconds": None},
    "checkpoint": {"every_generations": None, "every_seconds": 30},
    "evaluation": {"backend": "serial", "workers": None, "scheduler": None},
    "output": {"plot": False},
}

SCALARS = st.one_of(
    st.none(), st.booleans(), st.integers(min_value=-(10**30), max_value=10**30),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=30),
    st.sampled_from(["ga", "vega", "pymoo_de", "kubota", "rastrigin", "toolpath", "os:system", "processes", "dask",
                     "tournament", "per_bit", "two_point", "rank", "tcp://127.0.0.1:1", "", "-1", "1e400"]),
)
VALUES = st.recursive(SCALARS, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                        st.dictionaries(st.text(max_size=10), inner, max_size=4)),
                      max_leaves=12)


def paths(tree, prefix=()):
    """Every key path of a nested mapping, the mappings' own paths included."""
    for key, value in tree.items():
        yield prefix + (key,)
        if isinstance(value, dict):
            yield from paths(value, prefix + (key,))


PATHS = sorted(set(paths(BASE)))


@st.composite
def mutated(draw):
    tree = yaml.safe_load(yaml.safe_dump(BASE))  # a deep copy
    for _ in range(draw(st.integers(1, 4))):
        path = draw(st.sampled_from(PATHS))
        node = tree
        for key in path[:-1]:
            node = node.get(key) if isinstance(node, dict) else None
        if not isinstance(node, dict):
            continue
        action = draw(st.sampled_from(["set", "set", "delete", "unknown"]))
        if action == "set":
            node[path[-1]] = draw(VALUES)
        elif action == "delete":
            node.pop(path[-1], None)
        else:
            node[draw(st.text(min_size=1, max_size=12))] = draw(VALUES)
    return tree


def check(call) -> None:
    try:
        call()
    except EvoplanError as e:
        message = str(e)
        assert "\n" not in message and len(message) < 600, message[:1000]


def _dump(tree) -> str:
    return yaml.safe_dump(tree, allow_unicode=True)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_mutated_run_files_are_prepared_or_refused_in_one_line(tmp_path_factory, tree):
    path = tmp_path_factory.mktemp("fuzz") / "run.yaml"
    try:
        path.write_text(_dump(tree))
    except (UnicodeEncodeError, ValueError):  # surrogates in generated text: not a file one can write
        return
    check(lambda: prepare(load(str(path), None, []), str(path)))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.text(max_size=60), max_size=6).map("\n".join))
def test_random_text_is_yaml_or_one_line(text):
    check(lambda: load_text(text, "<fuzz>"))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from(["a: &a [1, 2]", "b: [*a, *a, *a]", "c: {x: *a}", "[", "]", "{", "}", "- ",
                                 "  ", "a: 1", "a: 2", "? x", ": y", "!!binary aGk=", "&x", "*x", "<<: *a",
                                 "!!python/name:os.system", "%YAML 1.1", "---", "..."]), max_size=12)
       .map("\n".join))
def test_structured_noise_is_yaml_or_one_line(text):
    check(lambda: load_text(text, "<fuzz>"))


def test_the_unmutated_tree_is_good(tmp_path):
    path = tmp_path / "run.yaml"
    path.write_text(_dump(BASE))
    prepared = prepare(load(str(path), None, []), str(path))
    assert prepared.config.algorithm.population == 8 and not math.isinf(prepared.config.problem.constraint_penalty)
