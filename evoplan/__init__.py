"""evoplan: evolutionary optimization of free-form surface toolpaths.

The Python API (loaded on first use, so that ``import evoplan`` stays light):

- :func:`minimize` (``evoplan.api``): one run of GA, VEGA, an adapter or a multi-objective
  algorithm on a pymoo problem, a problem name or a run configuration; returns a :class:`Result`.
- :class:`AskTell`: the same algorithms driven by a loop of your own.
- :class:`GA`, :class:`VEGA` and their settings :class:`GAConfig`, :class:`VEGAConfig`: the
  algorithms themselves (ask/tell over genotypes).
- :class:`Space`, :class:`Real`, :class:`Integer`, :class:`Categorical`: variables and the
  binary codec; :func:`make_problem`: a problem by name.
- :class:`ToolpathProblem` and its typed settings :class:`ToolpathSpec`: the toolpath problem.
"""

import importlib as _importlib

__version__ = "0.1.0"

_LAZY = {
    "minimize": "evoplan.api", "Result": "evoplan.api", "AskTell": "evoplan.api",
    "GA": "evoplan.algorithms", "GAConfig": "evoplan.algorithms", "VEGA": "evoplan.algorithms",
    "VEGAConfig": "evoplan.algorithms", "Space": "evoplan.space", "Real": "evoplan.space",
    "Integer": "evoplan.space", "Categorical": "evoplan.space",
    "make_problem": "evoplan.problem_factory", "ConfigError": "evoplan.errors",
    "EvoplanError": "evoplan.errors",
    "ToolpathProblem": "evoplan.problems.toolpath",
    "ToolpathSpec": "evoplan.problems.toolpath",
}

__all__ = ["__version__", *_LAZY]


def __getattr__(name: str):
    if name in _LAZY:
        value = getattr(_importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'evoplan' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
