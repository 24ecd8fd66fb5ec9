"""The embedded simulator next to a general-purpose Python robot simulator: the ``compare`` suite.

A fair comparison needs the same work on both sides, so the suite runs one small world
twice: two differential-drive robots of the e-puck's size, each with eight range
readings, two round obstacles inside a 1.0 m × 0.8 m walled arena, a 50 ms step, and a
trivial controller that reads each robot's ranges every step and turns when something is
within 5 cm of its body (the suite reports how often that happened on each side). On
IR-SIM (``pip install 'puckboard[compare]'``, i.e. ir-sim; its 2-D LiDAR with 8 beams
reaching 7 cm beyond the body, contact collisions, no rendering) and on puckboard's
engine (:class:`~puckboard.sim.world.World` with the physical e-puck's profile, whose 8
IR sensors cast 5 rays each through the response table, plus ground sensors, IMU and
encoders it computes whether read or not; each step's ``Proximity`` records built from
the world's arrays, as the embedded adapter builds them). Neither side runs a blackboard
or a behaviour tree: the sim suite measures puckboard's full stack.

IR-SIM is not a dependency of puckboard: without it the suite is skipped with a note
saying how to install it. Both simulators are timed the same way (median of
:data:`~puckboard.bench.timing.REPEATS` runs after 20 warm-up steps).
"""

from __future__ import annotations

import contextlib
import io
import math
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from .timing import REPEATS

__all__ = ["IRSIM_WORLD", "run_suite"]

#: The IR-SIM world: the same robots, obstacles, walls and step as :func:`_puckboard_scene`.
#: IR-SIM measures ranges from the robot's centre, the e-puck's IR sensors from its body:
#: its beams reach 7 cm beyond the body (0.037 + 0.07 m). The walls are four thin boxes
#: along the arena's sides (IR-SIM's LiDAR did not see a line-string obstacle). Contacts
#: push robots apart (``contact``), as the embedded engine does; with ``stop`` IR-SIM's
#: robots freeze at their first contact and then see a wall in 95 % of the steps.
IRSIM_WORLD = """\
world:
  height: 0.8
  width: 1.0
  step_time: 0.05
  sample_time: 0.05
  offset: [-0.5, -0.4]
  collision_mode: 'contact'
robot:
  - kinematics: {name: 'diff'}
    shape: {name: 'circle', radius: 0.037}
    state: [-0.3, 0.0, 1.5708]
    vel_max: [0.13, 6.3]
    sensors:
      - {name: 'lidar2d', range_min: 0, range_max: 0.107, angle_range: 6.2832, number: 8}
  - kinematics: {name: 'diff'}
    shape: {name: 'circle', radius: 0.037}
    state: [0.3, 0.0, -1.5708]
    vel_max: [0.13, 6.3]
    sensors:
      - {name: 'lidar2d', range_min: 0, range_max: 0.107, angle_range: 6.2832, number: 8}
obstacle:
  - shape: {name: 'circle', radius: 0.025}
    state: [0.0, 0.2, 0]
  - shape: {name: 'circle', radius: 0.025}
    state: [0.0, -0.2, 0]
  - shape: {name: 'rectangle', length: 1.04, width: 0.02}
    state: [0.0, 0.41, 0]
  - shape: {name: 'rectangle', length: 1.04, width: 0.02}
    state: [0.0, -0.41, 0]
  - shape: {name: 'rectangle', length: 0.02, width: 0.8}
    state: [0.51, 0.0, 0]
  - shape: {name: 'rectangle', length: 0.02, width: 0.8}
    state: [-0.51, 0.0, 0]
"""

#: Forward speed (m/s) and turn rate (rad/s) of the trivial controller.
FORWARD = 0.1
TURN = 1.0
#: Something closer than this to the body (m) makes the trivial controller turn.
NEAR = 0.05
#: The e-puck's body radius (m), which IR-SIM's ranges include.
BODY = 0.037


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Steps per second of the same two-robot world on IR-SIM and on puckboard's engine."""
    n_steps = steps or 1000
    try:
        # IR-SIM prints which plotting backends it could not load; keep the table clean
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            import irsim
    except ImportError as exc:
        return {
            "skipped": "IR-SIM is not installed (pip install 'puckboard[compare]') to compare "
            f"with: {exc}"
        }
    out: dict[str, Any] = {
        "world": "2 robots, 8 ranges each, 2 posts in a 1.0 m x 0.8 m walled arena, dt 50 ms",
        "steps_per_repeat": n_steps,
        "repeats": REPEATS,
        "irsim_version": getattr(irsim, "__version__", "unknown"),
    }
    theirs = [_irsim_rate(irsim, n_steps) for _ in range(REPEATS)]
    ours = [_puckboard_rate(n_steps) for _ in range(REPEATS)]
    irsim_rate = statistics.median(r for r, _ in theirs)
    our_rate = statistics.median(r for r, _ in ours)
    out["irsim_steps_per_s"] = round(irsim_rate, 1)
    out["puckboard_engine_steps_per_s"] = round(our_rate, 1)
    out["ratio"] = round(our_rate / irsim_rate, 2)
    # how often the controller saw something: the worlds are busy on both sides
    out["irsim_near_fraction"] = round(statistics.median(f for _, f in theirs), 2)
    out["puckboard_near_fraction"] = round(statistics.median(f for _, f in ours), 2)
    return out


def _irsim_rate(irsim: Any, n_steps: int) -> tuple[float, float]:
    """Steps per second, and the fraction of robot-steps that saw something near."""
    import numpy as np

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "compare.yaml"
        path.write_text(IRSIM_WORLD)
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            env = irsim.make(str(path), display=False, disable_all_plot=True, log_level="ERROR")
    forward = np.array([[FORWARD], [0.0]])
    turn = np.array([[FORWARD / 2], [TURN]])
    ids = [0, 1]

    near = [0]

    def step() -> None:
        actions = []
        for i in ids:
            if min(env.get_lidar_scan(i)["ranges"]) < BODY + NEAR:
                actions.append(turn)
                near[0] += 1
            else:
                actions.append(forward)
        env.step(actions, action_id=ids)

    try:
        return _timed(step, near, n_steps)
    finally:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            env.end(0)


def _puckboard_scene() -> Any:
    from ..scenario.scene import Arena, CircleObstacle, RobotSpec, Scene

    return Scene(
        "compare",
        robots=(
            RobotSpec("left", -0.3, 0.0, math.pi / 2, profile="epuck"),
            RobotSpec("right", 0.3, 0.0, -math.pi / 2, profile="epuck"),
        ),
        obstacles=(CircleObstacle(0.0, 0.2, 0.025), CircleObstacle(0.0, -0.2, 0.025)),
        arena=Arena(-0.5, -0.4, 0.5, 0.4),
        dt=0.05,
    )


def _puckboard_rate(n_steps: int) -> tuple[float, float]:
    """Steps per second, and the fraction of robot-steps that saw something near."""
    from ..records import Proximity
    from ..sim.world import World

    world = World(_puckboard_scene(), seed=0)
    wheel = world.profiles[0].wheel_radius
    axle = world.profiles[0].axle_length
    # the same body speeds as IR-SIM's actions, as wheel speeds (rad/s)
    forward = (FORWARD / wheel, FORWARD / wheel)
    turn_v, half = FORWARD / 2, TURN * axle / 2
    turn = ((turn_v - half) / wheel, (turn_v + half) / wheel)
    rows = [world.robot_arrays(i) for i in range(world.n)]
    ranges = [p.prox_range for p in world.profiles]
    robots = range(world.n)

    near = [0]

    def step() -> None:
        for i in robots:
            prox = Proximity(rows[i].prox_distance, rows[i].prox_raw, ranges[i])
            if min(prox.distance.tolist()) < NEAR:
                world.set_wheel_speeds(i, *turn)
                near[0] += 1
            else:
                world.set_wheel_speeds(i, *forward)
        world.step()

    return _timed(step, near, n_steps)


def _timed(step: Any, near: list[int], n_steps: int) -> tuple[float, float]:
    """Both simulators are timed alike: 20 warm-up steps, then ``n_steps`` timed; returns
    steps per second and the fraction of robot-steps (two robots) that saw something near."""
    for _ in range(20):
        step()
    near[0] = 0
    t0 = time.perf_counter()
    for _ in range(n_steps):
        step()
    return n_steps / (time.perf_counter() - t0), near[0] / (2 * n_steps)
