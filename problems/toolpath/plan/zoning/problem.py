"""Retired: zoning as genes is now a configuration of the one toolpath problem.

``ZonedToolpathProblem`` (``problem: toolpath_zoning``) lives in ``problems/toolpath/zoned.py``
and translates its old parameters into ``problem: toolpath`` with ``machine: 3axis``,
``spacing: scallop`` and a zoning method; this module keeps the old import path working.
"""

from ...zoned import CHOI_TOOLS, ZonedToolpathProblem

__all__ = ["CHOI_TOOLS", "ZonedToolpathProblem"]
