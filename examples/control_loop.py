"""Control loop architecture: read the sensors, compute, set the wheels — forever.

The simplest way to control a robot (thesis §2.1.1, Figure 2.1): one loop that reads a
sensor value, decides what to do with a few ``if`` statements, and sets the motors. No
layers, no arbiter, no blackboard to speak of: the decision is the body of the loop.

Here one e-puck follows the line of the ``line-follow`` scene with a hand-written
bang-bang rule on the three ground sensors:

* the line under the left sensor  → slow the left wheel (turn left, back onto it);
* the line under the right sensor → slow the right wheel;
* otherwise                        → straight on.

What to watch:

* the loop is *synchronous*: ``robot.step()`` advances the simulation by exactly one
  step after the wheels are set, so the run is the same on a fast or a slow computer;
* everything lives in one place. Easy to read — and hard to extend: add obstacle
  avoidance and the ``if`` cascade doubles (compare ``subsumption.py``).

Run it: ``python examples/control_loop.py``
"""

from __future__ import annotations

from puckboard.backends.embedded import open_embedded
from puckboard.records import Sensor
from puckboard.scenario.judge import Judge
from puckboard.scenario.scenefile import load_scene

SPEED = 2.0  # rad/s of wheel rotation (≈ 4 cm/s)
INNER = 0.3  # the inner wheel's fraction of SPEED while turning back onto the line


def main(duration: float = 60.0, seed: int = 0) -> dict[str, float]:
    """Follow the line for ``duration`` simulated seconds; return the judge's metrics."""
    scene = load_scene("line-follow")
    judge = Judge(scene)  # scores the run from the simulator's ground truth
    with open_embedded(scene, seed=seed) as connection:
        robot = connection.adapters["epuck"]
        world = connection.world
        robot.start_simulation()
        judge.update(world.time, world.poses, world.collisions)  # the start pose
        while robot.now() < duration:
            # 1. sense
            ground = robot.sense_all()[Sensor.GROUND]
            # 2. think
            left_dark, _, right_dark = ground.dark()  # dark = value below 0.5
            left = SPEED * INNER if left_dark else SPEED
            right = SPEED * INNER if right_dark else SPEED
            # 3. act, and let the simulated time advance by one step
            robot.set_wheel_speeds(left, right)
            robot.step()
            judge.update(world.time, world.poses, world.collisions)
    judge.finish()
    metrics = judge.metrics()[0]
    return {
        "sim_time_s": world.time,
        "distance_m": metrics.distance_m,
        "on_line_fraction": metrics.on_line_fraction,
        "progress_laps": metrics.progress_laps,
    }


if __name__ == "__main__":
    result = main()
    print(
        f"drove {result['distance_m']:.2f} m in {result['sim_time_s']:.0f} s, "
        f"{result['progress_laps']:.2f} laps, on the line "
        f"{100 * result['on_line_fraction']:.0f} % of the time"
    )
