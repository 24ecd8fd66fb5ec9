"""A recorded run as one self-contained HTML file: the web view's player, offline.

:func:`replay_html` inlines the page, its script, its styles and the run's replay
document (:func:`~puckboard.web.replay.replay_data`) into one file that opens with a
double click, from a course page or a USB stick: no server, no network, no install.
A Content-Security-Policy in the file forbids every request, so it provably needs none.
Writing it needs neither aiohttp nor a browser.
"""

from __future__ import annotations

import html
import json
import os
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..recording.atomic import write_atomically
from .replay import replay_data

if TYPE_CHECKING:
    from ..recording.recorder import Recording

__all__ = ["HTML_SUFFIXES", "replay_html", "write_replay_html"]

HTML_SUFFIXES = (".html", ".htm")

# Inline scripts and styles only; nothing may be fetched, not even a favicon.
_CSP = (
    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; "
    "img-src data:; base-uri 'none'; form-action 'none'"
)


def _static(name: str) -> str:
    return resources.files(__package__).joinpath("static").joinpath(name).read_text("utf-8")


def _script(code: str) -> str:
    if "</script" in code.lower():  # would end the element early; our files never do
        raise ValueError("a script of the page contains '</script'")
    return f"<script>\n{code}</script>"


def replay_html(recording: Recording | dict[str, Any]) -> str:
    """The player for ``recording`` (a :class:`~puckboard.recording.recorder.Recording`, or
    a replay document) as one HTML document."""
    data = recording if isinstance(recording, dict) else replay_data(recording)
    # JSON in a <script> element: "<" escaped so that no "</script>" or "<!--" can occur
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")
    page = _static("index.html")
    head = (
        f'<meta http-equiv="Content-Security-Policy" content="{_CSP}">\n'
        f"<style>\n{_static('view.css')}</style>"
    )
    replacements = {
        '<link rel="stylesheet" href="/view.css">': head,
        "<title>puckboard — live view</title>": (
            f"<title>puckboard — replay: {html.escape(str(data.get('title', '')))}</title>"
        ),
        '<script src="/view.js"></script>': (
            f'<script id="replay-data" type="application/json">{payload}</script>\n'
            + _script(_static("view.js"))
        ),
        '<script src="/replay.js"></script>': _script(_static("replay.js")),
    }
    for old, new in replacements.items():
        if old not in page:
            raise RuntimeError(f"the web view's index.html has no {old!r} to inline")
        page = page.replace(old, new)
    return page


def write_replay_html(recording: Recording | dict[str, Any], path: str | os.PathLike[str]) -> Path:
    """Write :func:`replay_html` to ``path`` (``.html``/``.htm``); returns the path."""
    path = Path(path)
    if path.suffix.lower() not in HTML_SUFFIXES:
        raise ValueError(f"the player is written as an .html file, got {str(path)!r}")
    text = replay_html(recording)
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_atomically(path, text.encode("utf-8"))
