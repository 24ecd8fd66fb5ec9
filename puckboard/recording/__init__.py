"""Recorded runs: what each robot sensed, decided and did, cycle by cycle, on disk.

One source for every after-the-fact view: the plots and animations of :mod:`puckboard.viz`
and the web view's player (:mod:`puckboard.web.replay`) read a recording; none of them
writes one. Apart from both, so that neither a picture nor a page is needed to record.

* :mod:`.recorder` — :class:`~.recorder.Recorder` (an episode observer),
  :class:`~.recorder.Recording` and :func:`~.recorder.load_recording`, the ``.npz``
  format;
* :mod:`.decisions` — each arbiter's decisions per tick (format 3);
* :mod:`.atomic` — files a reader never sees half-written.
"""

from __future__ import annotations

from .decisions import Decisions
from .recorder import FORMAT_VERSION, Recorder, Recording, load_recording

__all__ = ["FORMAT_VERSION", "Decisions", "Recorder", "Recording", "load_recording"]
