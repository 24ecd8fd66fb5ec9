"""Parametric tracks: a ``stadium``, ``rounded_rectangle`` or ``circle`` sampled to points.

A student describes a loop by its shape and size instead of typing dozens of points;
here the shape becomes the polyline a :class:`~puckboard.scenario.scene.Track` holds.
Straights are one segment each (exact), arcs are sampled every ``spacing`` metres, and
every shape starts at the middle of its bottom side heading +x and runs
counter-clockwise, so that ``track_position = 0.25`` (:mod:`.placement`) is a quarter of
the way round whatever the shape.
"""

from __future__ import annotations

import math

import numpy as np

from .reader import TableReader
from .scene import Track

__all__ = ["TRACK_KEYS", "TRACK_SHAPES", "read_track", "rounded_rectangle"]

TRACK_SHAPES = ("points", "stadium", "rounded_rectangle", "circle")
#: Every key a ``[track]`` may have, whatever its shape (an unknown one is refused first).
TRACK_KEYS = frozenset(
    ("shape", "width", "colour", "contrast", "points", "closed", "spacing", "centre", "heading")
    + ("heading_deg", "length", "radius", "size", "corner_radius")
)


def rounded_rectangle(width: float, height: float, r: float, spacing: float) -> np.ndarray:
    """Points of a rounded rectangle centred on the origin, counter-clockwise, starting
    at the middle of the bottom side heading +x."""
    hx, hy = width / 2.0 - r, height / 2.0 - r
    pieces: list[np.ndarray] = []

    def straight(a: tuple[float, float], b: tuple[float, float]) -> None:
        # one segment is exact for a straight; only the arcs need sampling
        if math.dist(a, b) > 1e-12:
            pieces.append(np.asarray([a], dtype=float))

    def arc(cx: float, cy: float, start: float) -> None:
        n = max(2, math.ceil(r * math.pi / 2.0 / spacing))
        phi = start + np.arange(n) / n * (math.pi / 2.0)
        pieces.append(np.stack([cx + r * np.cos(phi), cy + r * np.sin(phi)], axis=1))

    straight((0.0, -hy - r), (hx, -hy - r))
    arc(hx, -hy, -math.pi / 2.0)
    straight((hx + r, -hy), (hx + r, hy))
    arc(hx, hy, 0.0)
    straight((hx, hy + r), (-hx, hy + r))
    arc(-hx, hy, math.pi / 2.0)
    straight((-hx - r, hy), (-hx - r, -hy))
    arc(-hx, -hy, math.pi)
    straight((-hx, -hy - r), (0.0, -hy - r))
    pts = np.concatenate([p for p in pieces if len(p)])
    # drop exact duplicates where zero-length straights meet arcs
    keep = np.ones(len(pts), dtype=bool)
    keep[1:] = np.linalg.norm(np.diff(pts, axis=0), axis=1) > 1e-9
    return pts[keep]


def read_track(reader: TableReader) -> Track:
    """The ``[track]`` table: explicit ``points``, or a shape placed by ``centre`` and
    ``heading``."""
    shape = reader.string("shape", "points", choices=TRACK_SHAPES)
    width = reader.number("width", 0.015, unit="m", low=0.001, high=0.2)
    colour = reader.colour("colour", (20, 20, 20))
    contrast = reader.number("contrast", 1.0, unit="share of the line's contrast", low=0, high=1)
    if shape == "points":
        if not reader.has("points"):
            reader.fail("points", "", message="missing; expected a list of [x, y] points (m)")
        pts = reader.points("points", 2)
        closed = reader.boolean("closed", True)
        reader.finish()
        return Track(pts, width=width, closed=closed, colour=colour, contrast=contrast)
    spacing = reader.number("spacing", 0.01, unit="m", low=0.0005, high=0.1)
    cx, cy = reader.pair("centre") if reader.has("centre") else (0.0, 0.0)
    heading = reader.angle("heading", 0.0)
    pts = _shape_points(reader, shape, spacing)
    reader.finish()
    c, s = math.cos(heading), math.sin(heading)
    pts = pts @ np.array([[c, s], [-s, c]]) + np.array([cx, cy])
    return Track(pts, width=width, closed=True, colour=colour, contrast=contrast)


def _shape_points(reader: TableReader, shape: str, spacing: float) -> np.ndarray:
    """The points of a parametric ``shape`` centred on the origin, heading +x."""
    if shape == "stadium":
        length = reader.number("length", unit="m", low=0.0, high=100.0, required=True)
        radius = reader.number("radius", unit="m", low=0.01, high=100.0, required=True)
        return rounded_rectangle(length + 2 * radius, 2 * radius, radius, spacing)
    if shape == "rounded_rectangle":
        if not reader.has("size"):
            reader.fail("size", "", message="missing; expected [width, height] (m)")
        w, h = reader.pair("size", positive=True)
        r = reader.number("corner_radius", unit="m", low=0.01, required=True)
        if 2 * r > min(w, h):
            reader.fail("corner_radius", f"at most half the smaller side ({min(w, h) / 2:g} m)", r)
        return rounded_rectangle(w, h, r, spacing)
    # circle
    radius = reader.number("radius", unit="m", low=0.01, high=100.0, required=True)
    n = max(8, math.ceil(2 * math.pi * radius / spacing))
    phi = -math.pi / 2.0 + np.arange(n) / n * 2 * math.pi
    return np.stack([radius * np.cos(phi), radius * np.sin(phi)], axis=1)
