"""Blackboard architecture: modules that subscribe to keys and write derived keys.

In the blackboard architecture (thesis §2.1.1, Figure 2.5) one central store holds all
that is known. Independent modules tell it which information they are interested in;
when that information arrives they compute and write what they conclude back, where
other modules pick it up. Nobody calls anybody: modules only meet on the blackboard.

puckboard's robot adapters write sensor records (``ground``, ``encoders`` …) to the
blackboard. This example adds three modules:

* ``LinePosition`` (a :class:`~puckboard.estimation.knowledge.KnowledgeSource`) is interested in
  ``ground`` and writes ``percept/line_seen`` and ``percept/line_position``;
* ``Odometer`` (another knowledge source) is interested in ``encoders`` and writes
  ``estimate/distance_m``;
* a *subscriber* is interested in ``estimate/distance_m`` and notes a milestone every
  half metre.

The only behaviour layer, ``SteerToLine``, never looks at a sensor: it reads the derived
``percept/*`` keys. Knowledge sources run after sensing and before the layers tick, so
the layer sees percepts of the same instant.

What to watch:

* the derived keys carry the *time stamp of the reading they came from* (``stamps`` in
  the result): a percept says what was true when the sensor looked, however late it was
  computed;
* the odometer's distance agrees with the simulator's ground truth to within a few
  percent — but only roughly: wheels slip (see the FAQ on odometry drift).

Run it: ``python examples/blackboard.py``
"""

from __future__ import annotations

from typing import Any

from puckboard.behaviours import Controller, Cruise, Frame, Layer
from puckboard.blackboard import Record, Snapshot
from puckboard.control.episode import Episode
from puckboard.estimation.knowledge import KnowledgeSource
from puckboard.profile import EPUCK2
from puckboard.records import WheelCommand


class LinePosition(KnowledgeSource):
    """Sensor interpretation: where is the line under the robot (-1 right .. +1 left)?"""

    reads = ("ground",)
    writes = ("percept/line_seen", "percept/line_position")

    def compute(self, inputs: Snapshot) -> dict[str, Any] | None:
        ground = inputs.value("ground")
        if ground is None:
            return None
        darkness = 1.0 - ground.value
        seen = bool(ground.dark().any())
        position = float((darkness[0] - darkness[2]) / darkness.sum()) if seen else 0.0
        return {"percept/line_seen": seen, "percept/line_position": position}


class Odometer(KnowledgeSource):
    """Sensor integration: distance driven, from both wheel encoders."""

    reads = ("encoders",)
    writes = ("estimate/distance_m",)

    def reset(self) -> None:
        self.start: Any = None

    def compute(self, inputs: Snapshot) -> dict[str, Any] | None:
        enc = inputs.value("encoders")
        if enc is None:
            return None
        if self.start is None:
            self.start = enc
        turned = (enc.left - self.start.left) + (enc.right - self.start.right)
        return {"estimate/distance_m": EPUCK2.wheel_radius * turned / 2.0}


class SteerToLine(Layer):
    """Steer proportionally to the line's position; reads percepts, never sensors."""

    reads = ("percept/line_seen", "percept/line_position")

    def __init__(self, speed: float = 2.0) -> None:
        super().__init__()
        self.speed = speed

    def applies(self, frame: Frame) -> bool:
        return bool(frame.value("percept/line_seen", False))

    def command(self, frame: Frame) -> WheelCommand:
        turn = frame.value("percept/line_position")
        return WheelCommand(self.speed * (1.0 - turn), self.speed * (1.0 + turn))


def percept_follower() -> Controller:
    return Controller([SteerToLine(), Cruise()], name="percept-follower")


def main(duration: float = 40.0, seed: int = 0) -> dict[str, Any]:
    """Follow the line on percepts only; return derived values, stamps and milestones."""
    episode = Episode("line-follow", controller=percept_follower, seed=seed)
    LinePosition.for_each_robot(episode)
    Odometer.for_each_robot(episode)

    robot = episode.blackboard.namespace("epuck")
    milestones: list[tuple[float, float]] = []  # (time s, distance m)

    def on_distance(record: Record) -> None:
        if record.value >= 0.5 * (len(milestones) + 1):
            milestones.append((record.stamp, record.value))

    robot.subscribe("estimate/distance_m", on_distance)
    result = episode.run(duration, stop_early=False)
    return {
        "derived": {k: robot.get(k).value for k in ("percept/line_seen", "estimate/distance_m")},
        "stamps": {
            k: robot.get(k).stamp
            for k in ("ground", "percept/line_position", "estimate/distance_m")
        },
        "milestones": milestones,
        "true_distance_m": result.robots[0].distance_m,
        "on_line_fraction": result.robots[0].on_line_fraction,
    }


if __name__ == "__main__":
    out = main()
    for when, metres in out["milestones"]:
        print(f"t = {when:5.2f} s: the odometer passed {metres:.2f} m")
    print(
        f"odometry says {out['derived']['estimate/distance_m']:.3f} m, the simulator's ground "
        f"truth {out['true_distance_m']:.3f} m; on the line "
        f"{100 * out['on_line_fraction']:.0f} % of the time"
    )
    print("stamps of the last records:", {k: round(v, 2) for k, v in out["stamps"].items()})
