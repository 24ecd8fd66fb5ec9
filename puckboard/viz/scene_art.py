"""Drawing a scene's static parts on matplotlib axes: floor, track, obstacles, walls.

The track is drawn as filled geometry of its true width in metres (not a line width in
points), so it looks right at every zoom level and the ground sensors visibly sit on it
or beside it. Everything is drawn in the world frame (x right, y up, metres).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .style import LINE, rgb01

__all__ = ["draw_scene", "scene_bounds"]


def scene_bounds(scene: Any, poses: np.ndarray | None = None, margin: float = 0.08) -> tuple:
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


def draw_scene(ax: Any, scene: Any, *, labels: bool = True) -> None:
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
            cx, below = ob.x, ob.y - ob.radius
        else:
            vertices = np.asarray(ob.vertices)
            patch = Polygon(vertices, closed=True)
            cx, below = float(vertices[:, 0].mean()), float(vertices[:, 1].min())
        patch.set(facecolor=colour, edgecolor="#202020", linewidth=1.5, zorder=3)
        ax.add_patch(patch)
        if labels and ob.name:  # under the obstacle: a name never fits inside one
            ax.annotate(
                ob.name, (cx, below), xytext=(0, -3), textcoords="offset points",
                ha="center", va="top", fontsize=10, color="#303030", zorder=4,
            )  # fmt: skip
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
