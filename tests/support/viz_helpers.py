"""Shared helpers for the visual-tool tests."""

from __future__ import annotations

from viz_standin import StandInEpisode

from puckboard.recording.recorder import Recorder, Recording


def stand_in_recording(seconds: float = 2.0) -> Recording:
    ep = StandInEpisode()
    recorder = Recorder.for_episode(ep).attach(ep)
    ep.run(seconds)
    return recorder.close()
