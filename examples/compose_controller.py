"""Compose a controller: stack layers by priority, tune their parameters, compare.

A controller is a list of layers, highest priority first; the arbiter gives the wheels to
the first one that applies. Composing one is choosing the layers, their order and their
parameters — no other code. This example builds the thesis's improved controller out of
ready-made layers::

    1. FrontObstacleLeftTurn         something in front → always turn left first
    2. LineFollow(recovery=True)     on the line → follow it, sharp turns to regain it
    3. SideWallKeep(("right",))      obstacle on the right → hug it until the line
    4. Cruise                        otherwise straight on

and runs it against the stock V-REP controller on the two-robot pass, same seed.

What to watch:

* the printed tree: the order *is* the priority;
* ``controller.find("LineFollow")`` reaches a layer inside the controller to read or
  change a parameter — the same thing ``--set layer.LineFollow.inner_factor=...`` does on
  the command line;
* the outcome at the meeting: the stock controller's robots drive into each other
  (``collision``); the composed one lets them pass right side to right side. Whether
  both then find the line again depends on the seed; the tutorial (docs/tutorial.md)
  adds a layer for that.

Run it: ``python examples/compose_controller.py``
"""

from __future__ import annotations

from typing import Any

from puckboard.behaviours import (
    Controller,
    Cruise,
    FrontObstacleLeftTurn,
    LineFollow,
    SideWallKeep,
)
from puckboard.control.episode import run_episode


def composed(inner_factor: float = 0.20) -> Controller:
    """The improved controller, written out layer by layer."""
    return Controller(
        [
            FrontObstacleLeftTurn(),
            LineFollow(inner_factor=inner_factor, recovery=True),
            SideWallKeep(("right",)),
            Cruise(),
        ],
        name="composed",
        requires=("proximity",),  # stop rather than act on a stale proximity reading
    )


def main(duration: float = 120.0, seed: int = 0) -> dict[str, Any]:
    """Run the two-robot pass with the composed and the stock controller."""
    controller = composed()
    print(controller.ascii_tree())
    line = controller.find("LineFollow")
    print(f"LineFollow parameters: {line.parameters()}")
    return {
        "layers": [layer.name for layer in controller.layers],
        "composed": run_episode(
            "two-robot-pass", controller=composed, seed=seed, duration=duration
        ),
        "stock": run_episode("two-robot-pass", controller="stock", seed=seed, duration=duration),
    }


if __name__ == "__main__":
    out = main()
    for name in ("stock", "composed"):
        result = out[name]
        verdict = "passed" if result.success else f"failed: {result.failure}"
        met = all(robot.passed_other and robot.collisions == 0 for robot in result.robots)
        print(f"{name:9s} robots got past each other untouched: {met!s:5}  outcome: {verdict}")
