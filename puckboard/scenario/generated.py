"""Generated scenes: a new two-robot pass from each episode's seed, on a track nobody designed.

The shipped pass scenes are one loop we drew ourselves; a controller tuned on them may
have learnt the loop. A scene file with a ``[generate]`` table (``kind = "pass"``, the
shipped ``generated-pass``) is a *family* of scenes instead: every episode's seed draws
its own closed track, meeting place and obstacles from the ranges below, so a sweep over
seeds is a sweep over tracks. The rest of the file (robots' names, controllers and
colours, profile, noise, dt, goal) is kept. :func:`generated_data` draws one seed's file
data; :func:`.conversion.for_seed` builds its scene, which an
:class:`~puckboard.control.episode.Episode` does with its own seed, and
``puckboard scenes show generated-pass --seed N`` prints the result as a scene file that
``puckboard run`` runs to the same result.

The ranges, none chosen by how a controller fares on them:

* the loop is a rounded rectangle (stadiums and near-circles are special cases) of outer
  size ``SIZE_X`` × ``SIZE_Y``: a 1.6 × 0.8 m classroom table (two school desks side by
  side) with about 10 cm to spare, and both shipped loops (1.3 × 0.5 m, 1.0 × 0.6 m) inside;
* corner radii from ``MIN_CORNER`` (100 mm: the UK Micromouse and Robotics Society line
  follower rules' smallest bend; the stock line following turns on 4.4 cm) to half the
  short side (a stadium's half circle);
* the robots meet on a straight or in a bend, one or the other with equal odds; on a
  straight the loop keeps at least ``MIN_STRAIGHT`` of it;
* they start ``SEPARATION`` apart along the line, symmetric about the meeting place (the
  shipped scenes' 0.5 m on the straight and 1.0 m in the bend), facing each other;
* two obstacles stand on the line on the far side of the loop, ``OBSTACLE_GAP`` apart
  (the shipped 0.4 m inside), their middle within ``OBSTACLE_SHIFT`` of the point
  opposite the meeting place, so the robots pass one each, meet again between them and
  pass the other, as in the thesis's scene; each is a cylinder of radius
  ``CYLINDER_RADIUS`` or a box of sides ``BOX_SIDE`` along the line, with equal odds
  (assumed: objects at hand on a classroom table, the shipped 6 cm cylinders and the
  7 cm of the issue that found the gap inside);
* the run lasts as long per metre of lap as ``two-robot-pass`` (120 s for 3.17 m).

Line width, colours, noise and robots come from the file. The draws come from a
generator of their own, seeded ``[seed, GENERATE_STREAM]``, so neither the simulation's
noise nor a varied robot changes with the track.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["GENERATE_KEYS", "GENERATE_STREAM", "generated_data"]

#: The keys a ``[generate]`` table may have.
GENERATE_KEYS = frozenset(("kind",))
#: The third word of the track generator's seed (the ASCII of "TRAK").
GENERATE_STREAM = 0x5452414B

SIZE_X = (0.8, 1.4)  # m, the loop's outer width
SIZE_Y = (0.4, 0.7)  # m, its outer height
MIN_CORNER = 0.1  # m
MIN_STRAIGHT = 0.3  # m of straight left where the robots meet on one
SEPARATION = (0.5, 1.0)  # m along the line between the robots' starts
OBSTACLE_GAP = (0.3, 0.6)  # m along the line between the two obstacles
OBSTACLE_SHIFT = 0.15  # m: the obstacles' middle from the point opposite the meeting
CYLINDER_RADIUS = (0.02, 0.035)  # m
BOX_SIDE = (0.04, 0.07)  # m
SECONDS_PER_METRE = 120.0 / 3.17  # two-robot-pass: 120 s for its 3.17 m lap
SPACING = 0.01  # m between the sampled points of a bend (the scene files' default)


def generated_data(template: Mapping[str, Any], seed: int) -> dict[str, Any]:
    """The scene file data of seed ``seed``: ``template`` (a scene file's data with a
    ``generate`` table) with a drawn track, robot starts, obstacles and duration."""
    rng = np.random.default_rng([int(seed), GENERATE_STREAM])
    meet_on_straight = bool(rng.random() < 0.5)
    width = float(rng.uniform(*SIZE_X))
    height = float(rng.uniform(*SIZE_Y))
    top = height / 2 if not meet_on_straight else min(height / 2, (width - MIN_STRAIGHT) / 2)
    corner = float(rng.uniform(MIN_CORNER, top))
    lap = 2 * (width + height) - (8 - 2 * math.pi) * corner
    # arc length from the track's start (the middle of the bottom side, counter-clockwise)
    meet = 0.0 if meet_on_straight else (width / 2 - corner) + math.pi * corner / 4
    separation = float(rng.uniform(*SEPARATION))
    middle = meet + lap / 2 + float(rng.uniform(-OBSTACLE_SHIFT, OBSTACLE_SHIFT))
    gap = float(rng.uniform(*OBSTACLE_GAP))
    obstacles = [
        _obstacle(rng, k, (middle + side * gap / 2) % lap) for k, side in enumerate((-1, 1))
    ]
    data = {k: v for k, v in template.items() if k != "generate"}
    track = dict(data.get("track", {}))
    track.update(
        shape="rounded_rectangle", size=[width, height], corner_radius=corner, spacing=SPACING
    )
    data["track"] = track
    robots = [dict(r) for r in data.get("robots", [])]
    if len(robots) != 2:
        raise ValueError("a generated pass needs exactly two [[robots]] (their starts are drawn)")
    starts = ((meet - separation / 2) % lap, "along"), ((meet + separation / 2) % lap, "against")
    for robot, (distance, direction) in zip(robots, starts):
        robot.update(track_distance=distance, direction=direction)
    data["robots"] = robots
    data["obstacles"] = obstacles
    data["duration"] = round(SECONDS_PER_METRE * lap, 1)
    where = "on a straight" if meet_on_straight else "in a bend"
    data["description"] = (
        f"{str(data.get('description', '')).strip()} Seed {int(seed)}: a {width:.2f} × "
        f"{height:.2f} m loop with {corner * 100:.0f} cm corners (lap {lap:.2f} m); the robots "
        f"meet {where}."
    ).strip()
    return data


def _obstacle(rng: np.random.Generator, index: int, distance: float) -> dict[str, Any]:
    """One obstacle on the line at ``distance`` m along it: a cylinder or a box."""
    name = f"obstacle-{index + 1}"
    colour = [[200, 60, 40], [210, 150, 40]][index % 2]  # the pass scenes' two colours
    if rng.random() < 0.5:
        return {
            "name": name,
            "colour": colour,
            "shape": "circle",
            "track_distance": distance,
            "radius": float(rng.uniform(*CYLINDER_RADIUS)),
        }
    return {
        "name": name,
        "colour": colour,
        "shape": "box",
        "track_distance": distance,
        "size": [float(rng.uniform(*BOX_SIDE)), float(rng.uniform(*BOX_SIDE))],
    }
