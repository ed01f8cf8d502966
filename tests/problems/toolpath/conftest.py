"""Shared fixtures of the toolpath tests (analytic surfaces: ``toolpath_analytic.py``)."""

import pytest

from evoplan.problems.toolpath import ToolpathProblem


@pytest.fixture(scope="session")
def fountas_problem():
    """The default problem (Fountas surface, nine tools, paper ranges)."""
    return ToolpathProblem()
