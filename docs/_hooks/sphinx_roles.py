"""griffe extension (mkdocstrings): the Sphinx roles of evoplan's docstrings as links.

evoplan's docstrings name other objects as ``:func:`minimize```, ``:class:`~evoplan.space.Space```
or ``:mod:`evoplan.cache```; mkdocstrings renders docstrings as Markdown, where these roles
would show raw. Once a package is loaded, every docstring's roles become mkdocs-autorefs
references, the name resolved in the docstring's own scope (``minimize`` in ``evoplan.api``
is ``evoplan.api.minimize``). They are *optional* references: one whose target the API
reference does not render (a private module) shows as code, not as a broken link, so
``mkdocs build --strict`` stays quiet. A ``~`` keeps only the last part of the name as the text.
"""

from __future__ import annotations

import html
import re

import griffe

ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|attr|data|obj|exc|const):`(~?)([^`<>]+?)`")


def _target(obj: griffe.Object, name: str) -> str:
    """The full path of ``name`` as seen from ``obj`` (itself when already a full path); a
    dotted name resolves by its first part (``Space.named``: ``evoplan.space.Space.named``)."""
    first, _, rest = name.partition(".")
    scope = obj
    while scope is not None:
        try:
            base = scope.resolve(first)
        except (griffe.NameResolutionError, AttributeError, KeyError, ValueError):
            scope = scope.parent
            continue
        return f"{base}.{rest}" if rest else base
    return name


def rewrite(text: str, obj: griffe.Object) -> str:
    """``text`` with each role replaced by an optional autorefs link (see the module docstring)."""

    def link(m: re.Match) -> str:
        short, name = m.group(1) == "~", m.group(2).strip().removesuffix("()")
        shown = name.rsplit(".", 1)[-1] if short else name
        target = _target(obj, name)
        return f'<autoref identifier="{html.escape(target)}" optional><code>{html.escape(shown)}</code></autoref>'

    return ROLE.sub(link, text)


def _walk(obj: griffe.Object):
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from _walk(member)


class SphinxRoles(griffe.Extension):
    def on_package(self, *, pkg: griffe.Module, **kwargs) -> None:
        for obj in _walk(pkg):
            if obj.docstring is not None and ":" in obj.docstring.value:
                obj.docstring.value = rewrite(obj.docstring.value, obj)
