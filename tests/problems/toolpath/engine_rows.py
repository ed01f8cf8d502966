"""Test helper: rows of Fountas' five decisions (tool INDEX, step-over % of D, lead, tilt,
step mm) planned by the one engine (``Planner``, a single zone) and judged by its analytic
criteria (``analytic_criteria``, ``point_heights``)."""

import numpy as np

from evoplan.problems.toolpath.criteria.analytic import analytic_criteria, point_heights
from evoplan.problems.toolpath.plan.planner import Planner
from evoplan.problems.toolpath.spec import parse_tools
from evoplan.problems.toolpath.tools import ToolDatabase

OPTIONS = dict(allowance=0.5, feed_rate=1000.0, delta_l=40.0)


def database(tools) -> ToolDatabase:
    return tools if isinstance(tools, ToolDatabase) else parse_tools(tools)


def genes(X, five_axis=True) -> dict:
    X = np.atleast_2d(np.asarray(X, float))
    g = {"tool": X[:, 0].astype(int), "stepover": X[:, 1], "step": X[:, 4]}
    return g | ({"lead": X[:, 2], "tilt": X[:, 3]} if five_axis else {})


def plans(surface, tools, X, machine="5axis", place=False, **planner):
    """The single-zone plans (a ``PlanBatch``) of the rows of X."""
    return Planner(surface, database(tools), machine=machine, **planner).plan(
        genes(X, machine == "5axis"), place=place)


def criteria(surface, tools, X, machine="5axis", allowance=0.5, feed_rate=1000.0, **planner):
    """Every analytic criterion, each (n,), of the rows of X."""
    db = database(tools)
    return analytic_criteria(plans(surface, db, X, machine, **planner), surface, db,
                             genes(X, machine == "5axis"), allowance=allowance,
                             feed_rate=feed_rate, delta_l=40.0, machine=machine)


def heights(surface, tools, X, allowance=0.5, **planner):
    """(PlanBatch, per-point dict: h, kappa, w, normal) of the 5-axis rows of X."""
    db = database(tools)
    batch = plans(surface, db, X, **planner)
    return batch, point_heights(batch, surface, db, genes(X), allowance=allowance)
