"""Experiment commands (sweep, sensitivity, tune) run in this process on the session's
episodes.

A page's sweep runs episodes other tests run too: the sweeps page's first command is
``stock`` and ``improved`` on seeds 0-9 of the shipped scene, the acceptance tests'
episodes. Run as the reader runs it, it would start a worker process and run all of them
again. Inside :func:`sweeps_share_episodes` the command's workers are this process (the
sweep's own in-process executor, which gives the same rows as its worker processes:
tests/sweep test that) and each episode is the session's (tests/support/episodes.py):
computed once, whichever test asks first.

Only what fully determines an episode is its key: a shipped scene the sweep has not
changed, the controller (a shipped one's name, or a file's absolute path), the seed and
the settings. Anything else (a scene file, ``--duration``, a controller file named
relative to the test's folder) runs as it is, uncached.
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from episodes import episode

import puckboard.control.episode as episode_module
import puckboard.sweep as sweep_package
from puckboard.scenario import load_scene, scene_to_dict
from puckboard.sweep import InlineExecutor

__all__ = ["sweeps_share_episodes"]


class _ThisProcess(InlineExecutor):
    """The in-process executor, built and started as the command builds its pool."""

    def __init__(self, workers: int | None = None) -> None:
        super().__init__()

    def start(self) -> None:
        pass


@contextlib.contextmanager
def sweeps_share_episodes() -> Iterator[None]:
    """Within: experiment commands run their episodes here, from the session's cache."""
    real_run, real_pool = episode_module.run_episode, sweep_package.LocalExecutor

    def shared(
        scene: Any,
        *,
        controller: Any = None,
        seed: int = 0,
        duration: float | None = None,
        overrides: Mapping[str, Any] | None = None,
        **rest: Any,
    ) -> Any:
        name = getattr(scene, "name", scene)
        shipped = isinstance(name, str) and _is_shipped(scene, name)
        if not (shipped and _names_one_controller(controller)) or duration is not None or rest:
            return real_run(
                scene, controller=controller, seed=seed, duration=duration,
                overrides=overrides, **rest,
            )  # fmt: skip
        return episode(name, controller, seed, None, overrides)

    episode_module.run_episode = shared  # type: ignore[assignment]
    sweep_package.LocalExecutor = _ThisProcess  # type: ignore[assignment,misc]
    try:
        yield
    finally:
        episode_module.run_episode = real_run
        sweep_package.LocalExecutor = real_pool


def _is_shipped(scene: Any, name: str) -> bool:
    if isinstance(scene, str):
        return True
    shipped = _shipped_scene(name)
    return shipped is not None and scene_to_dict(scene) == shipped


@functools.cache
def _shipped_scene(name: str) -> dict[str, Any] | None:
    """The shipped scene called ``name`` in its explicit form, read once per process (a
    sweep asks for every one of its episodes); None when no shipped scene has the name."""
    try:
        return scene_to_dict(load_scene(name))
    except Exception:  # not a shipped scene's name
        return None


def _names_one_controller(spec: Any) -> bool:
    """A shipped controller's name, or a file by its absolute path: a relative path names
    a different file in each test's folder."""
    if not isinstance(spec, str):
        return False
    path = spec.rsplit(":", 1)[0]
    return ("/" not in spec and "\\" not in spec and ":" not in spec) or Path(path).is_absolute()
