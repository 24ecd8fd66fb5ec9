"""Plots of a recorded run: trajectories, arbitration timeline, sensor traces, wheels.

Each ``plot_*`` function takes a :class:`~puckboard.recording.recorder.Recording` and returns a
matplotlib figure (drawn off-screen, no window); :func:`save_plots` writes all four as
PNG or SVG. Titles carry the scenario, controller and seed; axes are in metres,
seconds and rad/s; robots and layers have the colours they have in the live view.

The arbitration timeline is the one to look at first when a controller misbehaves: one
band per robot, coloured by the layer in control at each moment, shows at a glance who
drove when (the stock controller's obstacle layer taking over on both robots at the
same instant, for example).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from ..recording.recorder import Recording
from .style import LINE, TYPE_SIZES, event_label, layer_colours, layer_order, robot_colours

__all__ = [
    "PLOT_FORMATS",
    "plot_arbitration",
    "plot_sensors",
    "plot_trajectories",
    "plot_wheels",
    "save_plots",
]

PLOT_FORMATS = ("png", "svg")


def _figure(width: float, height: float) -> Any:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _colours(rec: Recording) -> dict[str, str]:
    return robot_colours(rec.robot_names, rec.meta.get("colours"))


def _all_layers(rec: Recording) -> list[str]:
    """Every layer in priority order, then any others that took control."""
    used = {rec.layer_names[k] for k in np.unique(rec.layer) if k >= 0}
    return layer_order((rec.robot(r).layers for r in rec.robot_names), sorted(used))


def _style_axes(ax: Any) -> None:
    ax.tick_params(labelsize=TYPE_SIZES["tick"])
    ax.xaxis.label.set_size(TYPE_SIZES["label"])
    ax.yaxis.label.set_size(TYPE_SIZES["label"])
    ax.grid(True, alpha=0.3)


def plot_trajectories(rec: Recording) -> Any:
    """The scene with every robot's path, its start (circle) and end (triangle)."""
    from .animation import _bounds
    from .scene_art import draw_scene, label_obstacles

    fig = _figure(10, 6.5)
    ax = fig.add_subplot()
    draw_scene(ax, rec.scene, labels=False)  # named once the markers are down, clear of them
    xmin, xmax, ymin, ymax = _bounds(rec.scene, rec.pose[..., :2])
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)
    colours = _colours(rec)
    markers = []
    for name in rec.robot_names:
        s = rec.robot(name)
        ok = np.isfinite(s.pose[:, 0])
        if not ok.any():
            continue
        xy = s.pose[ok, :2]
        ax.plot(xy[:, 0], xy[:, 1], color=colours[name], lw=LINE["trail"], label=name, zorder=5)
        markers += ax.plot(*xy[0], "o", ms=12, color=colours[name], mec="white", mew=2, zorder=6)
        th = s.pose[ok, 2][-1]
        markers += ax.plot(
            *xy[-1], marker=(3, 0, np.degrees(th) - 90), ms=16, color=colours[name],
            mec="black", mew=1.5, zorder=6, ls="none",
        )  # fmt: skip
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"Trajectories: {rec.title}", fontsize=TYPE_SIZES["title"])
    _style_axes(ax)
    fig.draw_without_rendering()  # laid out as it will be saved: names are placed by size
    if rec.scene is not None:  # a recording made without its scene has none to name
        label_obstacles(ax, rec.scene, avoid=markers)
    from matplotlib.lines import Line2D

    handles, _ = ax.get_legend_handles_labels()
    handles += [
        Line2D([], [], marker="o", ls="none", color="#606060", ms=10, label="start"),
        Line2D([], [], marker=(3, 0, -90), ls="none", color="#606060", ms=12, label="end"),
    ]
    ax.legend(handles=handles, fontsize=TYPE_SIZES["legend"], loc="best", framealpha=0.9)
    return fig


def layer_spans(rec: Recording, robot: str) -> list[tuple[str | None, float, float]]:
    """(layer, start, end) runs of the layer in control for ``robot``; the last run ends
    one cycle after the last row."""
    s = rec.robot(robot)
    t = rec.time
    if len(t) == 0:
        return []
    step = float(np.median(np.diff(t))) if len(t) > 1 else 0.05
    idx = s.layer_index
    change = np.flatnonzero(np.diff(idx)) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [len(t)]])
    out = []
    for a, b in zip(starts, ends):
        k = int(idx[a])
        end = float(t[b]) if b < len(t) else float(t[-1]) + step
        out.append((rec.layer_names[k] if k >= 0 else None, float(t[a]), end))
    return out


def plot_arbitration(rec: Recording) -> Any:
    """One band per robot over time, coloured by the layer in control."""
    from matplotlib.patches import Patch

    names = list(rec.robot_names)
    layers = _all_layers(rec)
    lcol = layer_colours([*layers, "(none)"])
    fig = _figure(12, 2.4 + 0.85 * len(names))
    ax = fig.add_subplot()
    shares: dict[str, float] = dict.fromkeys(layers, 0.0)
    total = 0.0
    for row, name in enumerate(names):
        spans = layer_spans(rec, name)
        by_layer: dict[str | None, list[tuple[float, float]]] = {}
        for layer, a, b in spans:
            by_layer.setdefault(layer, []).append((a, b - a))
            if layer is not None:
                shares[layer] = shares.get(layer, 0.0) + (b - a)
            total += b - a
        y = len(names) - 1 - row
        for layer, bars in by_layer.items():
            colour = lcol.get(layer, "#d9d9d9") if layer is not None else "#d9d9d9"
            ax.broken_barh(bars, (y - 0.38, 0.76), facecolors=colour, edgecolor="none")
        switches = max(0, len(spans) - 1)
        ax.annotate(
            f"{switches} switch{'' if switches == 1 else 'es'}",
            (1.0, y),
            xycoords=("axes fraction", "data"),
            xytext=(14, 0),
            textcoords="offset points",
            va="center",
            fontsize=TYPE_SIZES["tick"],
        )
    handles_events = _draw_events(ax, rec, names)
    ax.set_yticks(range(len(names)), labels=list(reversed(names)), fontsize=TYPE_SIZES["label"])
    ax.set_ylim(-0.6, len(names) - 0.4)
    if len(rec):
        spans_end = max((b for n in names for _, _, b in layer_spans(rec, n)), default=0.0)
        start = float(rec.time[0])
        ax.set_xlim(start, spans_end + 0.01 * (spans_end - start))
    ax.set_xlabel("time (s)")
    ax.set_title(f"Which layer had control: {rec.title}", fontsize=TYPE_SIZES["title"])
    handles = [
        Patch(
            facecolor=lcol[layer],
            label=f"{layer} ({100 * shares.get(layer, 0.0) / total:.0f} %)" if total else layer,
        )
        for layer in layers
    ]
    handles += handles_events
    fig.legend(
        handles=handles, loc="outside lower center", ncol=min(4, max(1, len(handles))),
        fontsize=TYPE_SIZES["legend"], frameon=False,
    )  # fmt: skip
    _style_axes(ax)
    ax.grid(True, axis="x", alpha=0.3)
    ax.grid(False, axis="y")
    return fig


_EVENT_MARKERS = {  # kind: marker, colour, offset from the band's middle
    "collision": ("X", "black", 0.0),
    "passed_other": ("^", "white", 0.2),
    "passed_obstacle": ("D", "white", 0.2),
    "left_line": ("v", "#bbbbbb", -0.2),
    "back_on_line": ("o", "#bbbbbb", -0.2),
}
"""Line events sit low on a robot's band and passing events high, so events at the same
moment (passed the other robot and back on the line, say) do not hide each other."""


def _draw_events(ax: Any, rec: Recording, names: list[str]) -> list[Any]:
    """Mark the judge's events on the robots' bands; returns legend handles."""
    from matplotlib.lines import Line2D

    events = rec.meta.get("events") or []
    shown: dict[str, Any] = {}
    for ev in events:
        kind, robot, t = ev.get("kind", ""), ev.get("robot", ""), float(ev.get("time_s", 0))
        if robot not in names:
            if kind == "success":
                ax.axvline(t, color="#2ca02c", lw=3, ls="--")
                shown.setdefault(
                    kind, Line2D([], [], color="#2ca02c", lw=3, ls="--", label="success")
                )
            continue
        marker, colour, dy = _EVENT_MARKERS.get(kind, ("*", "#d62728", 0.0))
        y = len(names) - 1 - names.index(robot) + dy
        label = event_label(kind)
        size = 16 if marker == "*" else 11
        ax.plot(
            t, y, marker=marker, ms=size, color=colour, mec="black", mew=1.5, zorder=5,
            clip_on=False,
        )  # fmt: skip
        shown.setdefault(
            kind,
            Line2D(
                [], [], marker=marker, ms=size, color=colour, mec="black", ls="none", label=label
            ),
        )
    return list(shown.values())


def plot_sensors(rec: Recording) -> Any:
    """Per robot: the 8 IR distances as a heat strip and the 3 ground values as lines."""
    from ..records import GROUND_NAMES, PROX_NAMES

    names = list(rec.robot_names)
    fig = _figure(12, 1.0 + 3.6 * len(names))
    axes = fig.subplots(2 * len(names), 1, sharex=True, height_ratios=[1.2, 1] * len(names))
    t = rec.time
    t0, t1 = (float(t[0]), float(t[-1])) if len(t) else (0.0, 1.0)
    colours = _colours(rec)
    image = None
    for r, name in enumerate(names):
        s = rec.robot(name)
        ax_p, ax_g = axes[2 * r], axes[2 * r + 1]
        rng = float(rec.meta.get("prox_range") or 0.05)
        closeness = 100.0 * (1.0 - np.clip(s.proximity.T / rng, 0.0, 1.0))
        image = ax_p.imshow(
            closeness, aspect="auto", cmap="YlOrRd", vmin=0, vmax=100, origin="lower",
            extent=(t0, t1, -0.5, 7.5), interpolation="nearest",
        )  # fmt: skip
        ax_p.set_yticks(range(8), labels=[f"ps{k} {n}" for k, n in enumerate(PROX_NAMES)])
        ax_p.tick_params(axis="y", labelsize=TYPE_SIZES["tick"] - 3)
        ax_p.set_title(
            f"{name}: IR proximity (how close, % of range)", fontsize=TYPE_SIZES["label"],
            color=colours[name], loc="left", fontweight="bold",
        )  # fmt: skip
        for k, gname in enumerate(GROUND_NAMES):
            ax_g.plot(t, s.ground[:, k], lw=LINE["trace"], label=gname, color=f"C{k}")
        ax_g.axhline(0.5, color="#404040", ls="--", lw=1.2, label="line threshold")
        ax_g.set_ylim(-0.05, 1.05)
        ax_g.set_ylabel("ground (0..1)")
        ax_g.legend(
            fontsize=TYPE_SIZES["legend"] - 2, loc="upper left", bbox_to_anchor=(1.005, 1.0),
            frameon=False,
        )  # fmt: skip
        _style_axes(ax_g)
        ax_p.tick_params(axis="x", labelsize=TYPE_SIZES["tick"])
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(f"Sensors: {rec.title}", fontsize=TYPE_SIZES["title"])
    if image is not None:
        fig.colorbar(image, ax=list(axes[0::2]), label="closeness (%)", shrink=0.8, pad=0.01)
    return fig


def plot_wheels(rec: Recording) -> Any:
    """Per robot: the commanded left and right wheel speeds (rad/s) over time."""
    names = list(rec.robot_names)
    fig = _figure(12, 1.0 + 2.6 * len(names))
    axes = np.atleast_1d(fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0])
    colours = _colours(rec)
    for ax, name in zip(axes, names):
        s = rec.robot(name)
        # not the layer colours: these lines are wheels, not layers
        ax.plot(rec.time, s.wheels[:, 0], lw=LINE["trace"], color="#222222", label="left wheel")
        ax.plot(
            rec.time,
            s.wheels[:, 1],
            lw=LINE["trace"],
            color="#CC79A7",
            ls="--",
            label="right wheel",
        )
        ax.axhline(0.0, color="#404040", lw=1.0)
        ax.set_ylabel("rad/s")
        ax.set_title(
            f"robot {name}: wheel commands",
            fontsize=TYPE_SIZES["label"],
            color=colours[name],
            loc="left",
            fontweight="bold",
        )
        ax.legend(
            fontsize=TYPE_SIZES["legend"],
            loc="upper left",
            bbox_to_anchor=(1.005, 1.0),
            frameon=False,
        )
        _style_axes(ax)
    axes[-1].set_xlabel("time (s)")
    fig.suptitle(f"Wheels: {rec.title}", fontsize=TYPE_SIZES["title"])
    return fig


PLOTS = {
    "trajectories": plot_trajectories,
    "arbitration": plot_arbitration,
    "sensors": plot_sensors,
    "wheels": plot_wheels,
}


def save_plots(rec: Recording, out_dir: str | os.PathLike[str], fmt: str = "png") -> list[Path]:
    """Write every plot of ``rec`` into ``out_dir`` as ``<name>.<fmt>``; returns the paths."""
    fmt = fmt.lower().lstrip(".")
    if fmt not in PLOT_FORMATS:
        raise ValueError(f"plot format must be one of {', '.join(PLOT_FORMATS)}, got {fmt!r}")
    if len(rec) == 0:
        raise ValueError("the recording is empty: nothing to plot")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, fn in PLOTS.items():
        fig = fn(rec)
        path = out / f"{name}.{fmt}"
        # no timestamps in the files: the same run gives the same bytes
        meta = {"Date": None} if fmt == "svg" else {"Software": "puckboard"}
        fig.savefig(path, format=fmt, metadata=meta)
        written.append(path)
    return written
