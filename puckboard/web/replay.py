"""A recorded run as the web view's data: the whole run at once, for a page that scrubs.

The live view streams one frame at a time; a replay hands the page everything the
recording holds in one JSON document (:func:`replay_data`), and the page's player builds
each instant's frame from it, so a time slider, stepping by one tick and jumping to an
event cost no round trip. The same document is served by ``puckboard replay RUN.npz
--web`` (``/replay.json``) and inlined in the one-file export
(:mod:`puckboard.web.export`).

Arrays are sent column by column, flattened and rounded to what the page can show
(0.1 mm, 1 mrad, 1 ms), and the tree statuses as one digit per node and tick, which keeps
a two-minute run of two robots to a few hundred kilobytes. Missing values are ``null``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..behaviours.tracing import STATUS_NAMES
from ..profile import get_profile
from ..recording.recorder import Recording
from ..records import PROX_NAMES
from ..viz.scene_art import scene_bounds
from ..viz.style import event_label, layer_colours, layer_order, robot_colours
from .state import describe_scene

if TYPE_CHECKING:
    from .server import WebView

__all__ = ["REPLAY_FORMAT", "replay_data", "serve_replay"]

#: Name and version of the document :func:`replay_data` returns.
REPLAY_FORMAT = ("puckboard-replay", 1)

NO_TREE = (
    "this recording has no behaviour-tree data (recorded by an older puckboard, format "
    "{version}); record the run again to see which layers were asked"
)
NOT_RECORDED = "this robot's controller was not recorded: no behaviour tree to show"


def _flat(values: np.ndarray, digits: int) -> list[float | None]:
    """``values`` flattened and rounded; NaN and infinities become ``None`` (null)."""
    rounded = np.round(np.asarray(values, dtype=np.float64).ravel(), digits).tolist()
    return [v if math.isfinite(v) else None for v in rounded]


def _digits(codes: np.ndarray) -> str:
    """Small non-negative integers (0..9) as one string of digits."""
    digits = np.clip(np.asarray(codes).ravel(), 0, 9).astype(np.uint8) + ord("0")
    return digits.tobytes().decode("ascii")


def _scene_json(rec: Recording) -> dict[str, Any]:
    """The scene as the live view describes it, robots in the recording's order; a
    recording without a scene (a real robot's run) gets an empty arena around its path."""
    scene = rec.scene
    names = list(rec.robot_names)
    poses = rec.pose[:, :, :2] if len(rec) else None
    if scene is not None:
        out = describe_scene(scene, driver="recording")
        xmin, xmax, ymin, ymax = scene_bounds(scene, poses, margin=0.0)
    else:
        xmin, xmax, ymin, ymax = scene_bounds(None, poses, margin=0.05)
        out = {
            "name": rec.meta.get("scenario") or "recorded run", "description": "",
            "driver": "recording", "dt": rec.meta.get("dt"), "duration": rec.duration,
            "floor": "#ffffff", "robots": [], "obstacles": [], "dummies": [],
            "arena": None, "track": None,
        }  # fmt: skip
    out["bounds"] = [xmin, ymin, xmax, ymax]
    described = {r["name"]: r for r in out["robots"]}
    colours = robot_colours(names, rec.meta.get("colours") or {})
    profile = get_profile("epuck")
    robots = []
    for name in names:
        entry = described.get(name) or {
            "name": name,
            "colour": colours[name],
            "profile": profile.name,
            "radius": profile.body_radius,
            "sensors": [
                [round(p.x, 4), round(p.y, 4), round(p.heading, 4)] for p in profile.prox_poses
            ],
            "sensor_names": list(PROX_NAMES),
            "range": profile.prox_range,
        }
        robots.append(entry)
    out["robots"] = robots
    return out


def _events(rec: Recording) -> list[dict[str, Any]]:
    events = sorted(rec.meta.get("events") or [], key=lambda e: float(e.get("time_s", 0.0)))
    return [
        {"t": round(float(e.get("time_s", 0.0)), 3), "robot": e.get("robot"),
         "kind": str(e.get("kind", "")), "text": event_label(str(e.get("kind", "")))}
        for e in events
    ]  # fmt: skip


def _reads(rec: Recording, r: int, name: str) -> list[dict[str, Any]]:
    """Robot ``r``'s read keys: ages, fresh/stale, and values (or the array they repeat)."""
    d = rec.decisions
    if d is None:
        return []
    same_as = {"proximity": rec.proximity[:, r], "ground": rec.ground[:, r]}
    out = []
    for j, entry in enumerate(d.reads):
        key = entry["key"]
        if key not in (d.robot_reads.get(name) or ()):
            continue
        item: dict[str, Any] = {
            "key": key, "age": _flat(d.age[:, r, j], 3), "status": _digits(d.fresh[:, r, j]),
            "values": None, "same_as": None,
        }  # fmt: skip
        values = d.values.get(key)
        if values is not None:
            own = values[:, r]
            twin = same_as.get(key)
            if (
                twin is not None
                and twin.shape == own.shape
                and np.array_equal(twin, own, equal_nan=True)
            ):
                item["same_as"] = key  # the page reads the array it already has
            else:
                item["values"] = _flat(own, 4)
        out.append(item)
    return out


def replay_data(rec: Recording) -> dict[str, Any]:
    """Everything the page's player needs to show ``rec`` at any instant (JSON-ready)."""
    d = rec.decisions
    version = int(rec.meta.get("version") or 0)
    layer_names = list(rec.layer_names)
    robots = []
    for r, name in enumerate(rec.robot_names):
        nodes = None if d is None else d.trees.get(name)
        tree = None
        if d is not None and nodes:
            tree = _digits(d.status[:, r, : len(nodes)])
        robots.append({
            "name": name,
            "pose": _flat(rec.pose[:, r], 4),
            "wheels": _flat(rec.wheels[:, r], 3),
            "layer": rec.layer[:, r].astype(int).tolist(),
            "prox": _flat(rec.proximity[:, r], 4),
            "ground": _flat(rec.ground[:, r], 3),
            "nodes": nodes,
            "tree": tree,
            "tree_note": None if tree else (
                NO_TREE.format(version=version) if d is None else NOT_RECORDED
            ),
            "reads": _reads(rec, r, name),
        })  # fmt: skip
    name, number = REPLAY_FORMAT
    return {
        "format": name,
        "version": number,
        "title": rec.title,
        "recording_format": version,
        "scene": _scene_json(rec),
        "dt": rec.meta.get("dt"),
        "prox_range": rec.meta.get("prox_range"),
        "t": _flat(rec.time, 3),
        "layer_names": layer_names,
        "layer_colours": layer_colours(
            layer_order(
                (rec.robot(n).layers for n in rec.robot_names),
                [*layer_names, "(none)", "(stale inputs)"],
            )
        ),
        "tree_status": list(STATUS_NAMES),
        "reads": []
        if d is None
        else [{k: e.get(k) for k in ("key", "type", "labels", "unit")} for e in d.reads],
        "robots": robots,
        "events": _events(rec),
    }


def serve_replay(rec: Recording, *, host: str = "127.0.0.1", port: int = 8080) -> WebView:
    """Serve the player for ``rec`` at ``http://host:port/``; returns the started
    :class:`~puckboard.web.server.WebView` (close it to stop)."""
    from .server import WebView

    data = replay_data(rec)
    view = WebView(host=host, port=port)
    view.publish("scene", data["scene"])
    view.publish("replay", data)
    return view.start()
