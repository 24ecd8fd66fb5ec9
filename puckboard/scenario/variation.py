"""Variations: how each episode's robots (and world) are drawn from its seed, by name.

``--variation NAME`` (``run``, ``sweep``, ``tune``, ``serve``, ``sensitivity``; a sweep's
``variation`` parameter; ``run_episode(variation=...)``) names one :class:`Variation` of
this registry. Each says what it does to a scene for a seed and a line of help; the
command line's choices, the sweeps' checks and every report read them here, so a new one
is one entry:

* ``none``: every robot exactly as its profile says;
* ``plausible``: each robot drawn within its profile's sourced ranges
  (:mod:`.plausible`);
* ``reality-gap``: the same robots, in conditions drawn within sourced ranges too
  (:mod:`.reality_gap`).

A package adds one without editing puckboard, as it adds a backend: an entry point in
the ``puckboard.variations`` group naming a :class:`Variation` (in its
``pyproject.toml``::

    [project.entry-points."puckboard.variations"]
    worn-wheels = "my_package.variations:WORN_WHEELS"

), or :func:`register_variation` from Python. A built-in name is never replaced by an
installed one. A variation draws from generators of its own, seeded from the episode's
seed, so the simulation's own draws stay as they are.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Collection
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from .._plugins import offered
from ..errors import ProfileError

if TYPE_CHECKING:
    from .scene import Scene

__all__ = [
    "ENTRY_POINT_GROUP",
    "NONE",
    "PLAUSIBLE",
    "REALITY_GAP",
    "VARIATIONS",
    "Variation",
    "Varied",
    "check_variation",
    "get_variation",
    "register_variation",
    "variation_names",
    "variations_help",
    "vary",
    "vary_scene",
]

log = logging.getLogger(__name__)

#: The entry-point group an installed package names its variations in.
ENTRY_POINT_GROUP = "puckboard.variations"


class Drawn(Protocol):
    """What a variation drew beyond the robots, as a run reports it."""

    def to_dict(self) -> dict[str, Any]: ...


@dataclass(frozen=True)
class Varied:
    """A scene as a variation drew it, and what else it drew (reality-gap's conditions;
    ``None`` when nothing), so that what a run reports is what it ran, drawn once."""

    scene: Scene
    conditions: Drawn | None = None


@dataclass(frozen=True)
class Variation:
    """One way of drawing an episode's robots (and world) from its seed.

    ``vary(scene, seed, fixed)`` gives the scene the episode runs and what was drawn
    (:class:`Varied`); ``fixed`` names the settings the run sets itself (``--set``, a
    profile's measured link), which a variation that draws conditions keeps as set.
    ``help`` is one line for ``--help``.
    """

    name: str
    help: str
    vary: Callable[[Scene, int, Collection[str]], Varied]


def _as_is(scene: Scene, seed: int, fixed: Collection[str]) -> Varied:
    return Varied(scene)


# The built-in variations' draws load on first use: the command line lists the names
# while it builds its parser, before numpy may be imported.
def _plausible(scene: Scene, seed: int, fixed: Collection[str]) -> Varied:
    from .plausible import plausible_robots

    return Varied(plausible_robots(scene, seed))


def _reality_gap(scene: Scene, seed: int, fixed: Collection[str]) -> Varied:
    from .plausible import plausible_robots
    from .reality_gap import draw_conditions

    # the same robots as plausible draws for the seed, in conditions drawn besides, once
    conditions = draw_conditions(scene, seed, fixed)
    return Varied(conditions.apply(plausible_robots(scene, seed)), conditions)


NONE = Variation("none", "every robot exactly as its profile says", _as_is)
PLAUSIBLE = Variation(
    "plausible",
    "build each robot from numbers drawn within what the sources allow (a robot each; its "
    "controller still believes the profile)",
    _plausible,
)
REALITY_GAP = Variation(
    "reality-gap",
    "the plausible robots, in conditions drawn within sourced ranges too (noise levels, "
    "line contrast and width, obstacles' IR reflectance, a hand placement, a real link's "
    "control timing)",
    _reality_gap,
)

#: Every variation by name: the built-in ones, then the registered and installed ones.
VARIATIONS: dict[str, Variation] = {v.name: v for v in (NONE, PLAUSIBLE, REALITY_GAP)}
_BUILT_IN = frozenset(VARIATIONS)
_installed_read = False


def _read_installed() -> None:
    """Add the installed packages' variations (entry points) to :data:`VARIATIONS`, once."""
    global _installed_read
    if _installed_read:
        return
    _installed_read = True
    import pkgutil

    for name, target, package in offered(ENTRY_POINT_GROUP, "variation", _BUILT_IN):
        try:
            variation = pkgutil.resolve_name(target)
        except (ImportError, AttributeError, ValueError) as exc:
            log.warning("%s offers variation %r, which does not load: %s", package, name, exc)
            continue
        if not isinstance(variation, Variation) or variation.name != name:
            log.warning(
                "%s offers variation %r as %r, not a Variation of that name; left out",
                package,
                name,
                target,
            )
            continue
        VARIATIONS.setdefault(name, variation)


def register_variation(variation: Variation) -> None:
    """Make ``--variation NAME`` (and ``run_episode(variation=NAME)``) draw ``variation``;
    a built-in one cannot be replaced."""
    if variation.name in _BUILT_IN:
        raise ValueError(f"variation {variation.name!r} is built in; give yours another name")
    VARIATIONS[variation.name] = variation


def variation_names() -> list[str]:
    """Every variation's name, the built-in ones first."""
    _read_installed()
    return list(VARIATIONS)


def get_variation(name: str) -> Variation:
    """The variation called ``name``; a one-line
    :class:`~puckboard.errors.ProfileError` naming the known ones otherwise."""
    if not isinstance(name, str) or name not in VARIATIONS:
        _read_installed()
    try:
        return VARIATIONS[name]
    except (KeyError, TypeError):
        raise ProfileError(
            f"unknown variation {name!r}; use one of {', '.join(variation_names())}"
        ) from None


def check_variation(name: str) -> str:
    """``name`` if it names a variation, else a one-line ``ProfileError``."""
    return get_variation(name).name


def variations_help() -> str:
    """Every variation and what it does, in one line for help texts."""
    return "; ".join(f"{v.name}: {v.help}" for v in (VARIATIONS[n] for n in variation_names()))


def vary(
    scene: Scene, seed: int, variation: str = NONE.name, fixed: Collection[str] = ()
) -> Varied:
    """``scene`` as variation ``variation`` draws it for ``seed``, settings named in
    ``fixed`` kept as the run set them, with what else it drew (each drawn once)."""
    return get_variation(variation).vary(scene, int(seed), fixed)


def vary_scene(
    scene: Scene, seed: int, variation: str = NONE.name, fixed: Collection[str] = ()
) -> Scene:
    """``scene`` as :func:`vary` draws it (what else it drew left unsaid)."""
    return vary(scene, seed, variation, fixed).scene
