"""What installed packages offer puckboard: the entry points of a group, read when asked.

A package adds a backend (``puckboard.backends``) or a variation
(``puckboard.variations``) without editing puckboard by naming it in an entry-point group
of its ``pyproject.toml``. Every registry reads its group the same way: each entry's
name, target and the package that offers it, a name puckboard already has left out with a
warning naming the package that tried (a shipped name is never replaced).
"""

from __future__ import annotations

import logging
from collections.abc import Container

__all__ = ["offered"]

log = logging.getLogger(__name__)


def offered(group: str, kind: str, taken: Container[str]) -> list[tuple[str, str, str]]:
    """``(name, target, package)`` of every installed entry point in ``group`` whose name
    is not ``taken``; ``kind`` names what they offer in the warning about the others."""
    from importlib.metadata import entry_points

    found = []
    for ep in entry_points(group=group):
        package = ep.dist.name if ep.dist is not None else "an installed package"
        if ep.name in taken:
            log.warning(
                "%s offers a %s %r, which puckboard already has; keeping puckboard's",
                package,
                kind,
                ep.name,
            )
            continue
        found.append((ep.name, ep.value, package))
    return found
