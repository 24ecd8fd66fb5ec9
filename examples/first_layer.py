"""Write your first layer: a reflex that turns left when something blocks the way.

A layer is a small class with three parts:

* ``reads``: the blackboard keys it looks at (here only ``proximity``); reading any
  other key raises an error that names it, so a misspelt key cannot go unnoticed;
* ``applies(frame)``: *whether* it wants the wheels now;
* ``command(frame)``: *what* it does with them, a ``WheelCommand(left, right)`` in rad/s.

``frame`` is a snapshot of the robot's blackboard taken at the start of the tick; read
sensors by name (``frame.proximity.front_left`` is the distance in metres seen by the
front-left sensor, 0.05 when nothing is in range). A layer never talks to the robot: the
same class runs in the simulator, in CoppeliaSim and on a real e-puck.

This file checks the layer in two ways, as you would:

1. **by hand, on a fake robot** whose sensors you set: nothing in front → the layer does
   not apply and ``Cruise`` drives; an obstacle 2 cm ahead → the layer takes over and
   turns left;
2. **in the simulator**, in the walled ``arena`` scene: with the layer above ``Cruise``
   the robots bump into walls far less often than with ``Cruise`` alone.

What to watch: ``collisions`` with and without your layer, and how often it had control.

Run it: ``python examples/first_layer.py``
"""

from __future__ import annotations

from typing import Any

from puckboard import Controller, Cruise, FakeAdapter, Frame, Layer, WheelCommand, run_episode


class TurnLeftWhenBlocked(Layer):
    """Turn left on the spot while a front sensor sees something closer than ``distance``."""

    reads = ("proximity",)

    def __init__(self, distance: float = 0.03, speed: float = 2.0) -> None:
        super().__init__()
        self.distance = distance  # m
        self.speed = speed  # rad/s

    def applies(self, frame: Frame) -> bool:
        prox = frame.proximity
        if prox is None:  # no reading yet
            return False
        nearest = min(prox.diagonal_left, prox.front_left, prox.front_right, prox.diagonal_right)
        return nearest < self.distance

    def command(self, frame: Frame) -> WheelCommand:
        return WheelCommand(-self.speed / 2, self.speed)  # left wheel back, right forward


def with_my_layer() -> Controller:
    return Controller([TurnLeftWhenBlocked(), Cruise()], name="my first controller")


def cruise_only() -> Controller:
    return Controller([Cruise()], name="cruise only")


def check_by_hand() -> dict[str, str]:
    """Put the controller in front of two situations on a fake robot."""
    robot = FakeAdapter()
    controller = with_my_layer()
    seen = {}
    robot.set_proximity()  # nothing anywhere
    robot.sense_all()
    controller.tick(robot.ns)
    seen["nothing in front"] = controller.active_layer
    robot.set_proximity(front_right=0.02)  # an obstacle 2 cm ahead, slightly right
    robot.sense_all()
    command = controller.tick(robot.ns)
    seen["obstacle 2 cm ahead"] = controller.active_layer
    seen["turns"] = "left" if command.right > command.left else "right"
    robot.close()
    return seen


def main(duration: float = 60.0, seed: int = 0) -> dict[str, Any]:
    """Check the layer by hand, then in the arena with and without it."""
    by_hand = check_by_hand()
    mine = run_episode("arena", controller=with_my_layer, seed=seed, duration=duration,
                       stop_early=False)  # fmt: skip
    baseline = run_episode("arena", controller=cruise_only, seed=seed, duration=duration,
                           stop_early=False)  # fmt: skip
    return {
        "by_hand": by_hand,
        "collisions_with_layer": sum(r.collisions for r in mine.robots),
        "collisions_cruise_only": sum(r.collisions for r in baseline.robots),
        "distance_with_layer_m": sum(r.distance_m for r in mine.robots),
    }


if __name__ == "__main__":
    out = main()
    for situation, layer in out["by_hand"].items():
        print(f"{situation:22s} -> {layer}")
    print(
        f"in the arena: {out['collisions_with_layer']} collisions with your layer, "
        f"{out['collisions_cruise_only']} with Cruise alone "
        f"(robots drove {out['distance_with_layer_m']:.1f} m in all)"
    )
