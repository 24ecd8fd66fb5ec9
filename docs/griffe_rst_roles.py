"""A griffe extension for the API reference: show Sphinx roles as plain code.

puckboard's docstrings are written to read well in ``help()`` and in an editor, with
Sphinx-style cross-reference roles such as ``:class:`~puckboard.records.Proximity```.
Markdown has no such roles, so mkdocstrings would print the role's name literally. This
extension rewrites each role to a code span of the name as Sphinx would show it (the
last component when the target starts with ``~``), before the docstring is rendered.
"""

from __future__ import annotations

import re
from typing import Any

from griffe import Extension, Object

ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|attr|data|exc|obj|const):`(~?)([^`]+)`")


def _plain(match: re.Match[str]) -> str:
    tilde, target = match.groups()
    target = target.strip()
    if "<" in target and target.endswith(">"):  # :class:`text <target>`
        return f"`{target.split('<', 1)[0].strip()}`"
    return f"`{target.rsplit('.', 1)[-1] if tilde else target}`"


def plain_roles(text: str) -> str:
    """``text`` with every Sphinx cross-reference role turned into a code span."""
    return ROLE.sub(_plain, text)


class PlainSphinxRoles(Extension):
    """Rewrite the docstring of every object griffe loads."""

    def on_object(self, *, obj: Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = plain_roles(obj.docstring.value)
