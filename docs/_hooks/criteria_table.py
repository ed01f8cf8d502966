"""mkdocs hook: the table of toolpath criteria, from ``problems/toolpath/criteria/table.py``.

A line ``<!-- criteria-table -->`` in a page becomes the table (name, unit, weightable, cut
simulation, meaning), generated when the site is built, so it always lists the criteria the
code computes and accepts.
"""

from __future__ import annotations

import importlib

MARKER = "<!-- criteria-table -->"


def on_page_markdown(markdown, page, config, files):
    if MARKER not in markdown:
        return markdown
    table = importlib.import_module("evoplan.problems.toolpath.criteria.table")
    return markdown.replace(MARKER, table.markdown_table())
