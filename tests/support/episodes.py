"""Episodes run once per test session, whichever test asks first.

The acceptance tests and the tests of the pages' measured claims look at the same
episodes (the shipped scenes, a controller, a seed, a profile); an episode is fully
determined by those, so each is run once and its result shared, within a process and
between the session's worker processes (tests/support/session_cache.py). Ask for a
test's episodes together (:func:`episodes`): the worker processes then share the work
instead of one waiting while the other runs what both need.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from typing import Any

from session_cache import each

from puckboard.control.episode import run_episode
from puckboard.scenario import load_scene
from puckboard.scenario.result import EpisodeResult

__all__ = ["episode", "episodes"]

_Key = tuple[str, str, int, tuple[tuple[str, Any], ...]]
_known: dict[_Key, EpisodeResult] = {}  # this process's results


def episode(
    scene: str,
    controller: str,
    seed: int = 0,
    profile: str | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> EpisodeResult:
    """The result of one episode of a shipped scene (``profile`` None: the scene's)."""
    return episodes(scene, controller, [seed], profile, overrides)[0]


def episodes(
    scene: str,
    controller: str,
    seeds: Iterable[int],
    profile: str | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> list[EpisodeResult]:
    """The results of one episode per seed, in the order of ``seeds``."""
    settings = dict(overrides or {})
    if profile is not None:
        settings["robot.profile"] = profile
    if "robot.profile" in settings and settings["robot.profile"] == _scene_profile(scene):
        del settings["robot.profile"]  # given as an argument or in a sweep's settings
    frozen = tuple(sorted(settings.items()))
    keys: list[_Key] = [(scene, controller, int(s), frozen) for s in seeds]
    missing = [k for k in dict.fromkeys(keys) if k not in _known]
    found = each(
        [repr(("episode", *k)) for k in missing],
        lambda i: run_episode(
            missing[i][0], controller=missing[i][1], seed=missing[i][2],
            overrides=dict(missing[i][3]),
        ),
    )  # fmt: skip
    _known.update(zip(missing, found))
    return [_known[k] for k in keys]


@functools.cache
def _scene_profile(scene: str) -> str | None:
    """The profile every robot of the shipped scene has, None if they differ: naming it
    changes nothing, so the episode is the one asked for without it (one key, not two).
    """
    profiles = {robot.profile for robot in load_scene(scene).robots}
    return profiles.pop() if len(profiles) == 1 else None
