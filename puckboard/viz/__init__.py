"""Visual tools: live view, animations, plots, behaviour-tree diagrams, sensor monitor.

Each tool lives in its own module and imports matplotlib, Pillow, imageio or rich only
when it is used, so ``import puckboard.viz`` costs nothing. Every tool reads what every
backend provides (blackboard keys and the scene), so each works the same with the
embedded simulator, CoppeliaSim and a real e-puck. Recorded runs are in
:mod:`puckboard.recording.recorder`; ``puckboard.viz.hooks.attach`` wires the tools to a run.
In Jupyter, :func:`replay` shows a recorded run in the web view's player, inline.
"""

from __future__ import annotations

import html
import os
from typing import Any

__all__ = ["replay"]


def replay(recording: Any, *, height: int = 720) -> Any:
    """Show ``recording`` (a :class:`~puckboard.recording.recorder.Recording` or the path of
    one) in the web view's player, inline in a Jupyter notebook: the one-file export of
    ``puckboard replay --html`` in an iframe, so it needs no server. Returns an
    ``IPython.display.HTML`` object (a notebook shows it when it is a cell's last value).
    """
    from ..recording.recorder import load_recording
    from ..web.export import replay_html

    try:
        from IPython.display import HTML
    except ImportError:
        raise ImportError(
            "puckboard.viz.replay shows the player inside Jupyter and needs IPython "
            "(run it in a notebook); elsewhere write the player to a file: "
            "puckboard replay RUN.npz --html run.html"
        ) from None
    if isinstance(recording, (str, os.PathLike)):
        recording = load_recording(recording)
    page = html.escape(replay_html(recording), quote=True)
    return HTML(
        f'<iframe srcdoc="{page}" style="width: 100%; height: {int(height)}px; border: 0" '
        'sandbox="allow-scripts" title="puckboard replay"></iframe>'
    )
