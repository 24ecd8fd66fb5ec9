"""Episodes run once per test session, whichever test asks first.

The acceptance tests and the tests of the pages' measured claims look at the same
episodes (the shipped scenes, a controller, a seed, a profile); an episode is fully
determined by those, so each is run once and its result shared, within a process and
between the session's worker processes (tests/support/session_cache.py).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

from session_cache import once

from puckboard.control.episode import run_episode
from puckboard.scenario.result import EpisodeResult

__all__ = ["episode"]


def episode(
    scene: str,
    controller: str,
    seed: int = 0,
    profile: str | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> EpisodeResult:
    """The result of one episode of a shipped scene (``profile`` None: the scene's)."""
    settings = dict(overrides or {})
    if profile is not None:
        settings["robot.profile"] = profile
    return _episode(scene, controller, seed, tuple(sorted(settings.items())))


@functools.cache
def _episode(
    scene: str, controller: str, seed: int, settings: tuple[tuple[str, Any], ...]
) -> EpisodeResult:
    return once(
        repr(("episode", scene, controller, seed, settings)),
        lambda: run_episode(scene, controller=controller, seed=seed, overrides=dict(settings)),
    )
