"""Drawing a scene's static parts on matplotlib axes: floor, track, obstacles, walls.

The track is drawn as filled geometry of its true width in metres (not a line width in
points), so it looks right at every zoom level and the ground sensors visibly sit on it
or beside it. Everything is drawn in the world frame (x right, y up, metres).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .style import LINE, rgb01

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["draw_scene", "label_obstacles", "scene_bounds"]


def scene_bounds(
    scene: Scene | None, poses: np.ndarray | None = None, margin: float = 0.08
) -> tuple:
    """(xmin, xmax, ymin, ymax) that show the whole scene (and ``poses``, N×2+) with a margin."""
    xs: list[float] = []
    ys: list[float] = []
    if scene is not None:
        arena = getattr(scene, "arena", None)
        if arena is not None:
            xs += [arena.xmin, arena.xmax]
            ys += [arena.ymin, arena.ymax]
        track = getattr(scene, "track", None)
        if track is not None:
            xs += list(track.points[:, 0])
            ys += list(track.points[:, 1])
        for ob in getattr(scene, "obstacles", ()):
            if hasattr(ob, "radius"):
                xs += [ob.x - ob.radius, ob.x + ob.radius]
                ys += [ob.y - ob.radius, ob.y + ob.radius]
            else:
                xs += list(ob.vertices[:, 0])
                ys += list(ob.vertices[:, 1])
        for spec in getattr(scene, "robots", ()):
            xs.append(spec.x)
            ys.append(spec.y)
    if poses is not None and len(poses):
        p = np.asarray(poses, dtype=float).reshape(-1, np.shape(poses)[-1])
        ok = np.isfinite(p[:, 0]) & np.isfinite(p[:, 1])
        xs += list(p[ok, 0])
        ys += list(p[ok, 1])
    if not xs:
        return (-0.5, 0.5, -0.5, 0.5)
    return (min(xs) - margin, max(xs) + margin, min(ys) - margin, max(ys) + margin)


def track_path(track: Any) -> Any:
    """The track's ink as one matplotlib path: a rectangle of the track's width per
    segment and a disc at every vertex, all counter-clockwise so that the non-zero fill
    rule paints their union. One path draws far faster than hundreds of patches."""
    from matplotlib.path import Path as MplPath

    half = track.width / 2.0
    pieces = []
    for (x0, y0), (x1, y1) in track.segments():
        dx, dy = x1 - x0, y1 - y0
        length = float(np.hypot(dx, dy))
        if length == 0:
            continue
        nx, ny = -dy / length * half, dx / length * half
        corners = [(x0 - nx, y0 - ny), (x1 - nx, y1 - ny), (x1 + nx, y1 + ny), (x0 + nx, y0 + ny)]
        pieces.append(MplPath([*corners, corners[0]], closed=True))
    disc = MplPath.circle((0.0, 0.0), half)
    ring = np.asarray(disc.vertices, dtype=float)
    for x, y in track.points:
        pieces.append(MplPath(ring + (x, y), disc.codes))
    return MplPath.make_compound_path(*pieces)


def draw_scene(ax: Any, scene: Scene | None, *, labels: bool = True) -> None:
    """Draw ``scene``'s floor, track, obstacles and walls on ``ax`` (equal aspect, metres)."""
    from matplotlib.patches import Circle, PathPatch, Polygon, Rectangle

    ax.set_aspect("equal", adjustable="box")
    if scene is None:
        return
    ax.set_facecolor(rgb01(getattr(scene, "floor_colour", (235, 235, 225))))
    track = getattr(scene, "track", None)
    if track is not None:
        ax.add_patch(
            PathPatch(track_path(track), facecolor=rgb01(track.colour), edgecolor="none", zorder=1)
        )
    for ob in getattr(scene, "obstacles", ()):
        colour = rgb01(ob.colour)
        patch: Any
        if hasattr(ob, "radius"):
            patch = Circle((ob.x, ob.y), ob.radius)
        else:
            patch = Polygon(np.asarray(ob.vertices), closed=True)
        patch.set(facecolor=colour, edgecolor="#202020", linewidth=1.5, zorder=3)
        ax.add_patch(patch)
        if labels and ob.name:  # under the obstacle: a name never fits inside one
            _name(ax, ob, _SPOTS[0], placed=False)
    arena = getattr(scene, "arena", None)
    if arena is not None:
        ax.add_patch(
            Rectangle(
                (arena.xmin, arena.ymin),
                arena.xmax - arena.xmin,
                arena.ymax - arena.ymin,
                fill=False,
                edgecolor=rgb01(arena.colour),
                linewidth=LINE["wall"],
                zorder=2,
            )
        )


# Where an obstacle's name may go: (side, offset in points, alignment). Under it first, as
# the moving views put it; then above, then beside it.
_SPOTS = (
    ("below", (0, -3), {"ha": "center", "va": "top"}),
    ("above", (0, 3), {"ha": "center", "va": "bottom"}),
    ("right", (4, 0), {"ha": "left", "va": "center"}),
    ("left", (-4, 0), {"ha": "right", "va": "center"}),
)


def _anchor(ob: Any, side: str) -> tuple[float, float]:
    """The point of ``ob``'s outline (its bounding box's, for a polygon) on ``side``."""
    if hasattr(ob, "radius"):
        x0, x1, y0, y1 = ob.x - ob.radius, ob.x + ob.radius, ob.y - ob.radius, ob.y + ob.radius
    else:
        v = np.asarray(ob.vertices)
        x0, x1, y0, y1 = (float(v[:, 0].min()), float(v[:, 0].max()),
                          float(v[:, 1].min()), float(v[:, 1].max()))  # fmt: skip
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    return {"below": (cx, y0), "above": (cx, y1), "right": (x1, cy), "left": (x0, cy)}[side]


def _name(
    ax: Any, ob: Any, spot: tuple[str, tuple[int, int], dict[str, str]], *, placed: bool = True
) -> Any:
    """``ob``'s name at ``spot``; a ``placed`` name (:func:`label_obstacles`) is drawn over
    the trails, with a light edge that keeps it legible where one runs under it."""
    from matplotlib import patheffects

    side, offset, align = spot
    text = ax.annotate(
        ob.name, _anchor(ob, side), xytext=offset, textcoords="offset points", fontsize=10,
        color="#303030", zorder=7 if placed else 4, **align,
    )  # fmt: skip
    if placed:
        text.set_path_effects(
            [patheffects.withStroke(linewidth=2.5, foreground="white", alpha=0.8)]
        )
        text.set_in_layout(False)  # placed by measuring the laid-out axes: must not move them
    return text


def label_obstacles(ax: Any, scene: Scene, avoid: Sequence[Any] = ()) -> list[Any]:
    """Name every obstacle of ``scene`` beside it, where the name covers nothing else.

    Each name goes to the first of below, above, right and left of its obstacle where it
    covers none of the ``avoid`` artists (start and end markers, say), no obstacle, no
    name placed before and no track, and stays inside the axes; trails it would cross
    count against a spot too, a little. Where no spot is clear, the one covering least.
    Text is measured, so the figure must be laid out as it will be drawn (call
    ``fig.draw_without_rendering()`` first). Returns the names' text artists.
    """
    fig = ax.figure
    renderer = fig.canvas.get_renderer()
    hard = [a.get_window_extent(renderer) for a in avoid]
    hard += [p.get_window_extent(renderer) for p in ax.patches if p.get_zorder() == 3]
    track = next((p for p in ax.patches if p.get_zorder() == 1), None)
    ink = None if track is None else track.get_transform().transform_path(track.get_path())
    trails = [
        line.get_transform().transform(line.get_xydata())
        for line in ax.lines
        if line.get_marker() in (None, "", "None") and len(line.get_xydata()) > 1
    ]
    frame = ax.get_window_extent(renderer)
    placed = []
    for ob in getattr(scene, "obstacles", ()):
        if not ob.name:
            continue
        best: tuple[float, Any] | None = None
        for spot in _SPOTS:
            text = _name(ax, ob, spot)
            box = text.get_window_extent(renderer)
            cost = 1000.0 * sum(box.overlaps(other) for other in hard)
            cost += 1000.0 * (
                box.x0 < frame.x0 or box.x1 > frame.x1 or box.y0 < frame.y0 or box.y1 > frame.y1
            )
            cost += 100.0 * bool(ink is not None and ink.intersects_bbox(box, filled=True))
            cost += sum(int(box.count_contains(points)) for points in trails)
            if best is None or cost < best[0]:
                if best is not None:
                    best[1].remove()
                best = (cost, text)
            else:
                text.remove()
            if cost == 0:
                break
        assert best is not None
        hard.append(best[1].get_window_extent(renderer))
        placed.append(best[1])
    return placed
