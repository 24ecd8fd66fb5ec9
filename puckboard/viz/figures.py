"""What every figure of an experiment shares: its palette, its type size, and a figure
drawn off screen.

The sweep's, the sensitivity analyses', the study's and the estimation bench's figures
are read from the back of a lecture hall and by colour-blind readers: large type
(:data:`FONT`) and Okabe & Ito's palette (:data:`OKABE_ITO`, which stays distinguishable
for the common colour blindnesses and on washed-out projectors; the views of
:mod:`.style` take their colours from it too). One colour per series, in the order of
:data:`COLOURS`.

:func:`new_figure` draws on matplotlib's file renderer (Agg) without pyplot, so no
window opens and the backend of whoever calls it (a notebook's inline one) is left as
it is: library code never switches a backend. matplotlib is imported only when a
figure is made, so importing this module costs nothing.
"""

from __future__ import annotations

from typing import Any

__all__ = ["COLOURS", "FONT", "OKABE_ITO", "new_figure"]

#: Okabe & Ito's palette by name (Okabe, M. and Ito, K., "Color Universal Design", 2008).
OKABE_ITO = {
    "black": "#000000",
    "orange": "#E69F00",
    "sky_blue": "#56B4E9",
    "bluish_green": "#009E73",
    "yellow": "#F0E442",
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "reddish_purple": "#CC79A7",
}

#: One colour per series (controller × profile), in this order; yellow is left out: it
#: does not show on white.
COLOURS = tuple(
    OKABE_ITO[name]
    for name in (
        "blue",
        "vermillion",
        "bluish_green",
        "reddish_purple",
        "orange",
        "sky_blue",
        "black",
    )
)

#: Type size (points) of titles' and labels' base; ticks and legends a few points less.
FONT = 15


def new_figure(**options: Any) -> Any:
    """A matplotlib ``Figure`` (``options`` as ``Figure`` takes them: ``figsize``...) on
    the Agg renderer, to be written with ``savefig``; an ImportError naming the extra
    when matplotlib is missing."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as exc:
        raise ImportError("--plot needs matplotlib: pip install 'puckboard[viz]'") from exc
    fig = Figure(**options)
    FigureCanvasAgg(fig)
    return fig
