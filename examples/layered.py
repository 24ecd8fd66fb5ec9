"""Layered architecture: sensor interpretation → decision → actuation, bottom-up.

The layered architecture (thesis §2.1.1) splits control into levels, each with one area
of responsibility, each handing its result to the level above: *sensor interpretation*
turns raw readings into meaningful quantities, a *decision* level (navigation, with a
small model of the world) chooses what to do, and *robot control* turns that into motor
commands. Data flows up from the sensors, one level at a time.

Here the three levels are three small classes, wired into one puckboard ``Layer`` so the
framework can run them on any backend:

1. ``SensorInterpretation``: ground values → where the line is under the robot
   (−1 right … +1 left, ``None`` when no sensor sees it);
2. ``Decision``: that position, plus a memory of where the line was last seen (the
   level's model of the world) → an intent: follow the line, or search for it;
3. ``Actuation``: the intent → left/right wheel speeds within the robot's limits.

What to watch:

* each level can be tested and replaced alone; the interpretation knows nothing of
  wheels, the actuation nothing of sensors;
* the decision level's memory makes the robot turn *towards* the side it lost the line
  on, instead of driving off straight. ``intents`` in the result counts how often it
  followed and how often it searched; the proportional steering of level 3 is smooth
  enough that on this track it should not lose the line at all.

Run it: ``python examples/layered.py``
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

from puckboard.behaviours import Controller, Frame, Layer
from puckboard.control.episode import Episode
from puckboard.profile import EPUCK2
from puckboard.records import Ground, WheelCommand


# -- level 1: sensor interpretation -------------------------------------------------------
class SensorInterpretation:
    """Where is the line? A darkness-weighted position of the three ground sensors."""

    def __init__(self, threshold: float = 0.5) -> None:
        self.threshold = threshold

    def __call__(self, ground: Ground | None) -> float | None:
        if ground is None or not ground.dark(self.threshold).any():
            return None
        darkness = 1.0 - ground.value  # 0 white .. 1 black, for left, centre, right
        return float((darkness[0] - darkness[2]) / darkness.sum())


# -- level 2: decision, with a small model of the world -----------------------------------
@dataclass(frozen=True)
class Intent:
    kind: str  # "follow" or "search"
    turn: float  # -1 (hard right) .. +1 (hard left)


class Decision:
    """Follow the line while it is seen; else search on the side it was last seen."""

    def __init__(self) -> None:
        self.last_side = 0.0  # the world model: which side the line went

    def __call__(self, line_position: float | None) -> Intent:
        if line_position is not None:
            if abs(line_position) > 0.2:
                self.last_side = 1.0 if line_position > 0 else -1.0
            return Intent("follow", line_position)
        return Intent("search", 0.8 * self.last_side)


# -- level 3: actuation -------------------------------------------------------------------
class Actuation:
    """Turn an intent into wheel speeds (rad/s) the robot can actually do."""

    def __init__(self, speed: float = 2.0, limit: float = EPUCK2.max_wheel_speed) -> None:
        self.speed = speed
        self.limit = limit

    def __call__(self, intent: Intent) -> WheelCommand:
        left = self.speed * (1.0 - intent.turn)
        right = self.speed * (1.0 + intent.turn)
        return WheelCommand(min(left, self.limit), min(right, self.limit))


class LayeredController(Layer):
    """The three levels as one puckboard layer; ``intents`` counts what level 2 chose."""

    reads = ("ground",)

    def __init__(self) -> None:
        super().__init__()
        self.interpret = SensorInterpretation()
        self.decide = Decision()
        self.actuate = Actuation()
        self.intents: Counter[str] = Counter()

    def command(self, frame: Frame) -> WheelCommand:
        line_position = self.interpret(frame.ground)  # level 1
        intent = self.decide(line_position)  # level 2
        self.intents[intent.kind] += 1
        return self.actuate(intent)  # level 3


def layered() -> Controller:
    return Controller([LayeredController()], name="layered")


def main(duration: float = 60.0, seed: int = 0) -> dict[str, object]:
    """Follow the line of the ``line-follow`` scene; return metrics and level-2 intents."""
    episode = Episode("line-follow", controller=layered, seed=seed)
    result = episode.run(duration, stop_early=False)
    layer = episode.controllers["epuck"].find("LayeredController")
    assert isinstance(layer, LayeredController)
    robot = result.robots[0]
    return {
        "distance_m": robot.distance_m,
        "on_line_fraction": robot.on_line_fraction,
        "intents": dict(layer.intents),
    }


if __name__ == "__main__":
    out = main()
    print(
        f"drove {out['distance_m']:.2f} m, on the line {100 * out['on_line_fraction']:.0f} % "  # type: ignore[operator]
        f"of the time; decisions: {out['intents']}"
    )
