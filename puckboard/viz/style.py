"""One visual language for every view: colours per robot and per layer, font sizes.

The live view, the animations and the plots all take their colours from here, so a
layer is the same colour in the window, in the GIF and in the arbitration timeline, and
a robot keeps its colour everywhere. Layer colours come from the Okabe-Ito palette,
which stays distinguishable for colour-blind viewers and on washed-out projectors.

Nothing here imports matplotlib: colours are ``#rrggbb`` strings any library accepts.
"""

from __future__ import annotations

import zlib
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from .figures import FONT, OKABE_ITO

__all__ = [
    "EVENT_LABELS",
    "LINE",
    "NO_DATA_COLOUR",
    "TYPE_SIZES",
    "event_label",
    "hex_colour",
    "layer_colour",
    "layer_colours",
    "layer_order",
    "robot_colours",
    "text_colour",
]

TYPE_SIZES = {
    "title": FONT + 2,
    "label": FONT - 1,
    "tick": FONT - 3,
    "legend": FONT - 3,
    "annotation": FONT - 2,
}
"""Type sizes (points) by role, from the one :data:`~puckboard.viz.figures.FONT`: readable
on a projector at the back of a room."""

LINE = {"trail": 2.5, "trace": 2.0, "heading": 3.0, "body_edge": 3.5, "wall": 4.0}
"""Line widths (points)."""

NO_DATA_COLOUR = "#d9d9d9"

# Okabe-Ito, by role.
_VERMILLION = OKABE_ITO["vermillion"]
_BLUE = OKABE_ITO["blue"]
_ORANGE = OKABE_ITO["orange"]
_GREEN = "#4DAF4A"  # Set1 green: Okabe-Ito's bluish green reads as blue when small
_PURPLE = OKABE_ITO["reddish_purple"]
_SKY = OKABE_ITO["sky_blue"]
_YELLOW = OKABE_ITO["yellow"]
_GREY = "#999999"
_DARK = "#404040"
# Cruising is the layer that drives when nothing else does: a quiet brown, away from the
# robots' own green, blue and red so a timeline never mixes a layer up with a robot
_BROWN = "#8C564B"

_BY_KEYWORD: tuple[tuple[str, str], ...] = (
    ("obstacle", _VERMILLION),
    ("avoid", _VERMILLION),
    ("braitenberg", _VERMILLION),
    ("line", _BLUE),
    ("wall", _ORANGE),
    ("cruise", _BROWN),
    ("wander", _BROWN),
)
_EXTRA = (_PURPLE, _SKY, _YELLOW, _GREEN, "#7F7F7F", "#BCBD22", "#17BECF", "#9467BD")
#: What a layer takes when its role's colour is taken in its run.
_SPARE = (*_EXTRA, _VERMILLION, _BLUE, _ORANGE, _BROWN)

_ROBOT_PALETTE = ("#2ca02c", "#1f77b4", "#d62728", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2")


EVENT_LABELS = {
    "collision": "collision",
    "passed_other": "passed the other robot",
    "passed_obstacle": "passed an obstacle",
    "left_line": "left the line",
    "back_on_line": "back on the line",
    "lost_line": "lost the line",
    "turned_back": "turned back",
    "parallel_driving": "drove side by side",
    "stuck": "stuck",
    "success": "success",
}


def event_label(kind: str) -> str:
    """Words for a judge's event kind (``passed_other`` -> ``passed the other robot``)."""
    return EVENT_LABELS.get(kind, kind.replace("_", " "))


def layer_colour(name: str | None) -> str:
    """The colour of a layer, stable across runs, files and processes.

    Layers are coloured by role (obstacle avoidance vermillion, line following blue,
    wall keeping orange, cruising brown), so ``FrontBraitenbergAvoid`` in the stock
    controller and ``FrontObstacleLeftTurn`` in the improved one share a colour; other
    names get a colour from a hash of the name.
    """
    if name is None:
        return NO_DATA_COLOUR
    if name == "(none)":
        return _GREY
    if name.startswith("("):
        return _DARK
    lower = name.lower()
    for word, colour in _BY_KEYWORD:
        if word in lower:
            return colour
    return _EXTRA[zlib.crc32(name.encode()) % len(_EXTRA)]


def layer_colours(names: Sequence[str]) -> dict[str, str]:
    """Colours for the layers of one run, each its own: a layer keeps its role's colour
    (:func:`layer_colour`) unless a layer before it in ``names`` has it already, and then
    takes the first colour no layer has (``LineFollow`` blue, ``LineSearch`` below it
    another). Pass the layers in priority order, robot by robot
    (:func:`layer_order`), and every view of the run colours them alike."""
    out: dict[str, str] = {}
    used: set[str] = set()
    for name in names:
        if name in out:  # the same layer of another robot's controller
            continue
        colour = layer_colour(name)
        if not name.startswith("("):  # "(none)" and "(stale inputs)" keep theirs
            if colour in used:
                colour = next((c for c in _SPARE if c not in used), colour)
            used.add(colour)
        out[name] = colour
    return out


def layer_order(per_robot: Iterable[Sequence[str]], others: Iterable[str] = ()) -> list[str]:
    """Every robot's layers in priority order (robot by robot, each name once), then
    ``others``: the order :func:`layer_colours` is handed in every view."""
    names: list[str] = []
    for layers in per_robot:
        names += [n for n in layers if n not in names]
    return names + [n for n in others if n not in names]


def robot_colours(names: Sequence[str], given: Mapping[str, Any] | None = None) -> dict[str, str]:
    """A distinct colour per robot: the scene's colour when it has one, else a palette's."""
    given = given or {}
    out: dict[str, str] = {}
    for i, name in enumerate(names):
        rgb = given.get(name)
        colour = hex_colour(rgb) if rgb is not None else _ROBOT_PALETTE[i % len(_ROBOT_PALETTE)]
        if colour in out.values():
            colour = next(
                (c for c in _ROBOT_PALETTE if c not in out.values()),
                _ROBOT_PALETTE[i % len(_ROBOT_PALETTE)],
            )
        out[name] = colour
    return out


def rgb01(colour: Sequence[int]) -> tuple[float, float, float]:
    """A 0..255 RGB triple (as scenes store colours) as matplotlib's 0..1 floats."""
    r, g, b = (float(c) / 255.0 for c in colour[:3])
    return (r, g, b)


def hex_colour(rgb: Sequence[int]) -> str:
    """A 0..255 RGB triple (as scenes store colours) as ``#rrggbb``, clamped to the range."""
    r, g, b = (max(0, min(255, int(c))) for c in rgb[:3])
    return f"#{r:02x}{g:02x}{b:02x}"


def text_colour(background: str) -> str:
    """Black or white text for a ``#rrggbb`` background: whichever contrasts more by
    WCAG's relative luminance. White on every colour washes out on a projector on the
    light ones (orange ``#E69F00``: 2.1 : 1 against 9.8 : 1 for black). The web page
    applies the same rule (``textOn`` in ``web/static/view.js``)."""

    def linear(channel: int) -> float:
        c = channel / 255.0
        return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4

    text = background.lstrip("#")
    r, g, b = (int(text[i : i + 2], 16) for i in (0, 2, 4))
    luminance = 0.2126 * linear(r) + 0.7152 * linear(g) + 0.0722 * linear(b)
    # contrast with black (L + 0.05) / 0.05 against white 1.05 / (L + 0.05)
    return "#000000" if (luminance + 0.05) ** 2 > 0.0525 else "#ffffff"
