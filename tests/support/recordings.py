"""Recordings of shipped scenes, made once per test session, whichever test asks first.

The plots, the offline player's document, its page layout and its slider all look at the
same recorded run (the two-robot pass, seed 0, the scene's controllers); it is fully
determined by the scene and the seed, so it is recorded once and its file read by every
test that draws or replays it (tests/support/session_cache.py shares it between the
session's worker processes). A test that writes files of its own writes them elsewhere:
the recording's file is read only.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from session_cache import ENV, once

from puckboard.control.episode import Episode
from puckboard.recording.recorder import Recorder

__all__ = ["recorded_run"]


def recorded_run(scene: str, seed: int = 0) -> Path:
    """The recording (``.npz``) of one whole episode of the shipped ``scene``."""

    def record() -> str:
        # in the session's folder (removed when the session ends), else a temporary one
        folder = Path(tempfile.mkdtemp(prefix="recording-", dir=os.environ.get(ENV)))
        path = folder / f"{scene}-{seed}.npz"
        episode = Episode(scene, seed=seed)
        Recorder.for_episode(episode, path).attach(episode)
        episode.run()
        return str(path)

    return Path(once(repr(("recording", scene, seed)), record))
