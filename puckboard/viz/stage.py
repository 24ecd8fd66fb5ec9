"""The picture of a run at one instant: the whole scene plus a close-up of every robot.

At the scale of a whole arena an e-puck is a few pixels across, too small to see its
infrared rays or which ground sensor is on the line. The :class:`Stage` therefore shows
an overview (floor, track, obstacles, walls, every robot with its heading and trail, its
body rimmed in the colour of its active layer) beside one close-up per robot that
follows it, where the IR rays are coloured by reading (grey: nothing in range; yellow
to red: closer) and the three ground sensors show their grey value, rimmed in blue when
they see the line. Each close-up is titled with the robot's name and its active layer.

The same stage draws the live window and every frame of an animation, so both look
the same. It is updated from plain arrays (poses, distances, ground values, layer
names), never from a simulator, which keeps it backend-neutral.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..profile import EPUCK2, get_profile
from .scene_art import draw_scene, scene_bounds
from .style import LINE, TYPE_SIZES, event_label, layer_colour, layer_colours

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["Stage"]

ZOOM_MAX_ROBOTS = 3
"""Above this many robots the stage shows the overview only."""

UNPLACED_X, UNPLACED_Y = 1.0e4, 1.0e4
"""Where robots without a pose are drawn (m): nowhere near any scene."""

NEWS_SECONDS = 3.0
"""How long (s of run time) a judge's event stays on screen."""

_RAY_IDLE = (0.55, 0.55, 0.55, 0.55)


class Stage:
    """A figure showing robots in a scene; call :meth:`update` with each new state."""

    def __init__(
        self,
        fig: Any,
        scene: Scene | None,
        robot_names: Sequence[str],
        *,
        colours: Mapping[str, str],
        layers: Sequence[str] = (),
        title: str = "",
        zoom: bool | None = None,
        zoom_width: float = 0.30,
        bounds: tuple[float, float, float, float] | None = None,
        cycle: float = 0.05,
    ) -> None:
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        self.fig = fig
        self.scene = scene
        self.names = tuple(robot_names)
        self.colours = dict(colours)
        self.zoom_width = zoom_width
        self._closeup_text = f"close-up, {zoom_width * 100:.0f} cm wide"
        self._unplaced_text = "no pose known: robot-centred"
        # the judge stamps a cycle's events at the end of the cycle, one period after
        # the sensing time the recording shows
        self._event_slack = cycle + 1e-6
        n = len(self.names)
        self.zoom = (n <= ZOOM_MAX_ROBOTS) if zoom is None else zoom
        self.profiles = [_profile_of(scene, name) for name in self.names]
        self._prox_geometry = np.array(
            [[(s.x, s.y, s.heading) for s in p.prox_poses] for p in self.profiles]
        )  # N×8×3
        self._ground_geometry = np.array(
            [[(s.x, s.y) for s in p.ground_poses] for p in self.profiles]
        )  # N×3×2
        self._prox_range = np.array([p.prox_range for p in self.profiles])

        fig.set_facecolor("white")
        legend_layers = list(dict.fromkeys([*layers, "(none)"]))
        n_handles = len(layers) + n
        ncol = max(1, min(n_handles, 3 if self.zoom else 5))
        bottom = 0.08 + 0.05 * math.ceil(n_handles / ncol)  # room for the legend
        if self.zoom:
            grid = fig.add_gridspec(
                n, 2, width_ratios=(1.75, 1), left=0.06, right=0.985, bottom=bottom,
                top=0.88, wspace=0.08, hspace=0.22,
            )  # fmt: skip
            self.overview = fig.add_subplot(grid[:, 0])
            self.closeups = [fig.add_subplot(grid[i, 1]) for i in range(n)]
            for ax in self.closeups:
                ax.set_animated(True)  # redrawn every frame: the view follows the robot
        else:
            grid = fig.add_gridspec(1, 1, left=0.08, right=0.97, bottom=bottom, top=0.88)
            self.overview = fig.add_subplot(grid[0, 0])
            self.closeups = []

        xmin, xmax, ymin, ymax = bounds or scene_bounds(scene)
        ov = self.overview
        draw_scene(ov, scene)
        ov.set_xlim(xmin, xmax)
        ov.set_ylim(ymin, ymax)
        ov.set_xlabel("x (m)", fontsize=TYPE_SIZES["label"])
        ov.set_ylabel("y (m)", fontsize=TYPE_SIZES["label"])
        ov.tick_params(labelsize=TYPE_SIZES["tick"])
        self._title = fig.text(
            0.06, 0.955, title, fontsize=TYPE_SIZES["title"], fontweight="bold", va="center"
        )
        self._footer = fig.text(
            0.985, 0.015, "", fontsize=TYPE_SIZES["tick"], ha="right", va="bottom", color="#505050"
        )
        self._clock = fig.text(
            0.985,
            0.955,
            "",
            fontsize=TYPE_SIZES["title"],
            ha="right",
            va="center",
            family="monospace",
        )

        self._footer.set_animated(True)
        self._clock.set_animated(True)
        self._news = fig.text(
            0.06, 0.912, "", fontsize=TYPE_SIZES["label"], va="center", color="#8b0000",
            fontweight="bold",
        )  # fmt: skip
        self._news.set_animated(True)
        self._background: Any = None
        self._own_draw = False

        # per axes, per robot artists
        self._artists: list[dict[str, Any]] = []
        all_axes = [ov, *self.closeups]
        for k, ax in enumerate(all_axes):
            detailed = k > 0 or not self.zoom
            arts: dict[str, Any] = {"ax": ax, "detailed": detailed, "robots": []}
            for i, name in enumerate(self.names):
                arts["robots"].append(self._robot_artists(ax, i, name, detailed))
            self._artists.append(arts)
        for i, ax in enumerate(self.closeups):
            draw_scene(ax, scene, labels=False)
            ax.set_xticks([])
            ax.set_yticks([])
            for spine in ax.spines.values():
                spine.set_edgecolor(self.colours[self.names[i]])
                spine.set_linewidth(4)
            ax.set_xlabel(self._closeup_text, fontsize=TYPE_SIZES["tick"], labelpad=4)
        self._closeup_labels = [ax.xaxis.label for ax in self.closeups]
        self._closeup_titles = [
            ax.set_title("", fontsize=TYPE_SIZES["label"], fontweight="bold", color="white", pad=6)
            for ax in self.closeups
        ]

        lcol = layer_colours(legend_layers)
        handles: list[Any] = [
            Patch(facecolor=lcol[name], edgecolor="none", label=name) for name in layers
        ]
        handles += [
            Line2D([], [], color=self.colours[name], linewidth=LINE["trail"] * 2, label=name)
            for name in self.names
        ]
        if handles:
            fig.legend(
                handles=handles,
                loc="lower left",
                bbox_to_anchor=(0.05, 0.0),
                ncol=ncol,
                fontsize=TYPE_SIZES["legend"],
                frameon=False,
                handlelength=1.4,
                columnspacing=1.2,
            )
        self._layer_colours = lcol

    def _robot_artists(self, ax: Any, i: int, name: str, detailed: bool) -> dict[str, Any]:
        from matplotlib.collections import LineCollection
        from matplotlib.lines import Line2D
        from matplotlib.patches import Circle

        colour = self.colours[name]
        radius = self.profiles[i].body_radius
        trail = Line2D([], [], color=colour, linewidth=LINE["trail"], alpha=0.75, zorder=5)
        ax.add_line(trail)
        # the ring (active layer's colour) stands apart from the body (robot's colour)
        ring = Circle(
            (0.0, 0.0), radius * 1.3, facecolor="none", edgecolor="#606060",
            linewidth=LINE["body_edge"], zorder=8, visible=False,
        )  # fmt: skip
        ax.add_patch(ring)
        body = Circle(
            (0.0, 0.0), radius, facecolor=colour, edgecolor="white", linewidth=1.0,
            zorder=10, visible=False,
        )  # fmt: skip
        ax.add_patch(body)
        heading = Line2D(
            [], [], color="white", linewidth=LINE["heading"], solid_capstyle="round", zorder=11
        )
        ax.add_line(heading)
        arts = {"trail": trail, "body": body, "ring": ring, "heading": heading}
        if not self.zoom:  # no close-up titles: label each robot with its active layer
            arts["label"] = ax.text(
                0.0, 0.0, "", fontsize=TYPE_SIZES["annotation"], color="white", fontweight="bold",
                ha="center", va="bottom", zorder=13, clip_on=True,
            )  # fmt: skip
        if detailed:
            rays = LineCollection([], linewidths=2.0, zorder=10.5, capstyle="round")
            ax.add_collection(rays)
            ground = ax.scatter(
                [], [], s=45, marker="s", zorder=12, linewidths=2.0, edgecolors="#808080"
            )
            arts.update(rays=rays, ground=ground)
        for artist in arts.values():
            artist.set_animated(True)  # drawn over a cached background, see render()
        return arts

    # -- updating --------------------------------------------------------------------------
    def update(
        self,
        time: float,
        pose: np.ndarray,
        proximity: np.ndarray,
        ground: np.ndarray,
        layers: Sequence[str | None],
        trails: Sequence[np.ndarray] | None = None,
        events: Sequence[Mapping[str, Any]] = (),
    ) -> None:
        """Show the state at ``time``: ``pose`` N×3, ``proximity`` N×8 distances (m),
        ``ground`` N×3 (0..1), ``layers`` the active layer per robot, ``trails`` one
        K×2 array of past positions per robot, ``events`` the judge's events so far
        (the last few seconds' are shown under the title)."""
        pose = np.array(pose, dtype=float)
        # A robot without a pose (a real e-puck has no ground truth) is drawn facing up
        # at a spot of its own far outside the scene, so its close-up still shows what
        # it senses and decides, robot-centred, while the overview leaves it out.
        lost = ~np.isfinite(pose).all(axis=1)
        for k in np.flatnonzero(lost):
            pose[k] = (UNPLACED_X + 10.0 * float(k), UNPLACED_Y, math.pi / 2)
        for j, label in enumerate(self._closeup_labels):
            text = self._unplaced_text if lost[j] else self._closeup_text
            if label.get_text() != text:
                label.set_text(text)
        proximity = np.asarray(proximity, dtype=float)
        ground = np.asarray(ground, dtype=float)
        self._clock.set_text(f"t = {time:.1f} s")
        recent = [
            (f"{e['robot']}: " if e.get("robot") else "") + event_label(str(e.get("kind", "")))
            for e in events
            if time - NEWS_SECONDS <= float(e.get("time_s", -1e9)) <= time + self._event_slack
        ]
        self._news.set_text("   ".join(dict.fromkeys(recent[-3:])))
        rays_xy, ray_colours, ray_widths = self._rays(pose, proximity)
        ground_xy = self._ground_points(pose)
        for arts in self._artists:
            for i, ra in enumerate(arts["robots"]):
                x, y, th = pose[i]
                known = math.isfinite(x) and math.isfinite(y)
                if trails is not None:
                    tr = trails[i]
                    ra["trail"].set_data(tr[:, 0], tr[:, 1])
                ra["body"].set_visible(known)
                ra["ring"].set_visible(known)
                if "label" in ra:
                    ra["label"].set_visible(known)
                ra["heading"].set_visible(known and math.isfinite(th))
                if not known:
                    if "rays" in ra:
                        ra["rays"].set_segments([])
                        ra["ground"].set_offsets(np.empty((0, 2)))
                    continue
                ra["body"].set_center((x, y))
                ra["ring"].set_center((x, y))
                ra["ring"].set_edgecolor(self._colour_of(layers[i]))
                if math.isfinite(th):
                    r = self.profiles[i].body_radius
                    ra["heading"].set_data([x, x + r * math.cos(th)], [y, y + r * math.sin(th)])
                if "label" in ra:
                    label = ra["label"]
                    label.set_position((x, y + 1.5 * self.profiles[i].body_radius))
                    label.set_text(f"{self.names[i]}: {layers[i] or '?'}")
                    label.set_bbox(
                        {"facecolor": self._colour_of(layers[i]), "edgecolor": "none", "pad": 2}
                    )
                if "rays" in ra:
                    ok = np.isfinite(proximity[i]).all()
                    ra["rays"].set_segments(rays_xy[i] if ok else [])
                    ra["rays"].set_color(ray_colours[i])
                    ra["rays"].set_linewidths(ray_widths[i])
                    g = ground[i]
                    if np.isfinite(g).all():
                        ra["ground"].set_offsets(ground_xy[i])
                        grey = np.clip(g, 0.0, 1.0)
                        ra["ground"].set_facecolors(np.stack([grey, grey, grey], axis=1))
                        ra["ground"].set_edgecolors(
                            ["#0072B2" if v < 0.5 else "#909090" for v in g]
                        )
                    else:
                        ra["ground"].set_offsets(np.empty((0, 2)))
        half = self.zoom_width / 2.0
        for i, ax in enumerate(self.closeups):
            x, y = pose[i, 0], pose[i, 1]
            if math.isfinite(x) and math.isfinite(y):
                ax.set_xlim(x - half, x + half)
                ax.set_ylim(y - half, y + half)
            name = layers[i] or "no decision yet"
            self._closeup_titles[i].set_text(f"{self.names[i]}: {name}")
            self._closeup_titles[i].set_bbox(
                {"facecolor": self._colour_of(layers[i]), "edgecolor": "none", "pad": 3}
            )

    # -- rendering -------------------------------------------------------------------------
    def render(self) -> None:
        """Draw the current state onto the figure's canvas, fast.

        Everything that never changes (the overview's floor, axes, ticks, legend, the
        title) is rendered once and cached as a bitmap; each frame restores it and draws
        only the moving parts and the close-ups. This makes a frame several times
        cheaper than a full redraw, which is what keeps the live view smooth and a
        long GIF quick to render. After the GUI redraws the figure (a resize, a zoom)
        :meth:`on_draw_event` takes that drawing as the new background.
        """
        canvas = self.fig.canvas
        if self._background is None:
            self._own_draw = True
            try:
                canvas.draw()
            finally:
                self._own_draw = False
            self._background = canvas.copy_from_bbox(self.fig.bbox)
        canvas.restore_region(self._background)
        self._draw_moving()

    def _draw_moving(self) -> None:
        draw = self.fig.draw_artist
        for k, arts in enumerate(self._artists):
            ax = arts["ax"]
            if k > 0 or ax.get_animated():
                draw(ax)
            robots = sorted(
                (a for ra in arts["robots"] for a in ra.values()), key=lambda a: a.get_zorder()
            )
            for artist in robots:
                draw(artist)
            if k > 0:
                for spine in ax.spines.values():
                    draw(spine)
        draw(self._clock)
        draw(self._news)
        draw(self._footer)

    def on_draw_event(self, _event: Any = None) -> None:
        """After the GUI redrew the figure (resize, zoom, expose): keep that as the new
        background and put the moving parts back on top; the caller blits."""
        if self._own_draw:
            return
        self._background = self.fig.canvas.copy_from_bbox(self.fig.bbox)
        self._draw_moving()

    def frame_rgb(self) -> np.ndarray:
        """Render and return the figure's pixels as an H×W×3 uint8 array (Agg canvases)."""
        self.render()
        return np.asarray(self.fig.canvas.buffer_rgba())[..., :3].copy()

    def set_footer(self, text: str) -> None:
        """A line of help or status text at the bottom right (keys, 'finished', ...)."""
        self._footer.set_text(text)

    def key_colours(self) -> list[str]:
        """Colours that carry meaning in this figure (for palettes of indexed images)."""
        return [*self._layer_colours.values(), *self.colours.values(), "#0072B2", "#909090"]

    def _colour_of(self, layer: str | None) -> str:
        if layer is None:
            return "#606060"
        colour = self._layer_colours.get(layer)
        if colour is None:
            colour = self._layer_colours[layer] = layer_colour(layer)
        return colour

    def _rays(self, pose: np.ndarray, prox: np.ndarray) -> tuple[np.ndarray, list, list]:
        """IR ray segments (N×8×2×2), colours and widths from poses and distances."""
        geo = self._prox_geometry
        x, y, th = pose[:, 0:1], pose[:, 1:2], pose[:, 2:3]
        c, s = np.cos(th), np.sin(th)
        sx = x + c * geo[:, :, 0] - s * geo[:, :, 1]
        sy = y + s * geo[:, :, 0] + c * geo[:, :, 1]
        ang = th + geo[:, :, 2]
        rng = self._prox_range[:, None]
        d = np.where(np.isfinite(prox), np.clip(prox, 0.0, rng), rng)
        ex, ey = sx + d * np.cos(ang), sy + d * np.sin(ang)
        segs = np.stack([np.stack([sx, sy], -1), np.stack([ex, ey], -1)], axis=2)
        closeness = np.clip(1.0 - d / rng, 0.0, 1.0)  # 0 nothing .. 1 touching
        colours, widths = [], []
        for i in range(len(pose)):
            ci, wi = [], []
            for k in range(geo.shape[1]):
                if d[i, k] >= rng[i, 0] - 1e-9:
                    ci.append(_RAY_IDLE)
                    wi.append(1.5)
                else:
                    q = 0.3 + 0.7 * closeness[i, k]  # yellow -> red
                    ci.append((0.94 - 0.1 * q, 0.89 * (1 - q) + 0.1, 0.26 * (1 - q), 1.0))
                    wi.append(3.5)
            colours.append(ci)
            widths.append(wi)
        return segs, colours, widths

    def _ground_points(self, pose: np.ndarray) -> np.ndarray:
        geo = self._ground_geometry
        x, y, th = pose[:, 0:1], pose[:, 1:2], pose[:, 2:3]
        c, s = np.cos(th), np.sin(th)
        gx = x + c * geo[:, :, 0] - s * geo[:, :, 1]
        gy = y + s * geo[:, :, 0] + c * geo[:, :, 1]
        return np.stack([gx, gy], axis=-1)


def _profile_of(scene: Scene | None, name: str) -> Any:
    """Robot ``name`` as built (its drawn truth if it has one): what the stage draws."""
    if scene is not None:
        for spec in getattr(scene, "robots", ()):
            if spec.name == name:
                try:
                    actual = getattr(spec, "actual", None)
                    return actual if actual is not None else get_profile(spec.profile)
                except (KeyError, ValueError):
                    break
    return EPUCK2
