"""How the simulator's cost grows with the number of robots: the ``scale`` suite.

``run_suite(steps)`` runs the ``swarm`` scene's arena (walls, three obstacles) with 2, 10,
30 and 50 e-pucks on the full stack (blackboard, the improved controller on every robot,
simulator, camera off) and reports steps per second, the real-time factor and the cost
per robot-step. The robots stand on a 20 cm grid inside the walls, clear of the
obstacles, with headings spread round the circle, so they meet walls, obstacles and each
other from the first seconds: the costly case for the sensors. A flat cost per
robot-step means the simulator scales linearly; a rising one means something costs more
than linearly in the number of robots (a pairwise test, for instance).
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import TYPE_CHECKING, Any

from .timing import REPEATS, median_seconds

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["PHASES", "ROBOT_COUNTS", "grid_robots", "run_suite", "swarm_with"]

#: Robot counts measured by the suite.
ROBOT_COUNTS: tuple[int, ...] = (2, 10, 30, 50)
GRID = 0.2  # m between robot start positions
CLEARANCE = 0.12  # m from a start position to any obstacle or wall


def grid_robots(scene: Scene, n: int) -> tuple[Any, ...]:
    """``n`` robots on a grid inside ``scene``'s arena, clear of its obstacles."""
    from ..scenario.scene import CircleObstacle, RobotSpec

    arena = scene.arena
    if arena is None:
        raise ValueError(f"scene {scene.name!r} has no arena to place robots in")
    cells = []
    y = arena.ymin + CLEARANCE
    while y <= arena.ymax - CLEARANCE + 1e-9:
        x = arena.xmin + CLEARANCE
        while x <= arena.xmax - CLEARANCE + 1e-9:
            clear = True
            for ob in scene.obstacles:
                if isinstance(ob, CircleObstacle):
                    gap = math.hypot(x - ob.x, y - ob.y) - ob.radius
                else:
                    cx, cy = ob.vertices.mean(axis=0)
                    reach = max(math.hypot(vx - cx, vy - cy) for vx, vy in ob.vertices)
                    gap = math.hypot(x - cx, y - cy) - reach
                clear = clear and gap > CLEARANCE
            if clear:
                cells.append((x, y))
            x += GRID
        y += GRID
    if n > len(cells):
        raise ValueError(f"the arena of {scene.name!r} holds at most {len(cells)} robots")
    # every k-th cell, so a few robots spread over the whole arena, not one corner
    step = len(cells) / n
    chosen = [cells[int(k * step)] for k in range(n)]
    golden = math.pi * (3.0 - math.sqrt(5.0))  # headings spread evenly round the circle
    return tuple(
        RobotSpec(
            f"epuck{k + 1}",
            x,
            y,
            math.remainder(k * golden, math.tau),
            controller="improved",
            profile="epuck",
        )
        for k, (x, y) in enumerate(chosen)
    )


def swarm_with(n: int) -> Any:
    """The shipped ``swarm`` scene's arena and obstacles with ``n`` robots."""
    from ..scenario.scenefile import load_scene

    scene = load_scene("swarm")
    return dataclasses.replace(scene, robots=grid_robots(scene, n), name=f"swarm-{n}")


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Full-stack steps/s and µs per robot-step for each of :data:`ROBOT_COUNTS`, and
    where a robot-step's time goes (CPU µs per robot-step in each phase of the cycle)."""
    from ..backends.embedded import open_embedded
    from ..behaviours import load_controller
    from ..control.loop import ControlLoop

    cycles = steps or 400
    out: dict[str, Any] = {"cycles_per_repeat": cycles, "repeats": REPEATS}
    rows: dict[str, Any] = {}
    for n in ROBOT_COUNTS:
        scene = swarm_with(n)
        per_cycle = []
        for _ in range(REPEATS):
            conn = open_embedded(scene, seed=0)
            try:
                pairs = [(a, load_controller("improved")) for a in conn.adapters.values()]
                loop = ControlLoop(pairs)
                loop.run(cycles=20, close=False)  # warm-up
                t0 = time.perf_counter()
                loop.run(cycles=cycles, close=False)
                per_cycle.append((time.perf_counter() - t0) / cycles)
            finally:
                conn.close()
        seconds = median_seconds(per_cycle)
        rows[f"{n} robots"] = {
            "steps_per_s": round(1.0 / seconds, 1),
            "realtime_factor": round(scene.dt / seconds, 1),
            "us_per_robot_step": round(seconds / n * 1e6, 1),
            "cpu_us_per_robot_step": _phases(scene, cycles, n),
        }
    out["by_robot_count"] = rows
    return out


#: The phases of a cycle as :func:`_phases` reports them.
PHASES = (
    "sensing (adapter records, blackboard)",
    "arbitration (py_trees tick, wheel command)",
    "engine (world.step)",
)


def _phases(scene: Scene, cycles: int, n: int) -> dict[str, float]:
    """CPU µs per robot-step in each phase, from one run of ``cycles`` cycles driven by
    hand as :meth:`ControlLoop.cycle` drives them (CPU time: other programs on the
    machine disturb it much less than the wall clock)."""
    from ..backends.embedded import open_embedded
    from ..behaviours import load_controller

    conn = open_embedded(scene, seed=0)
    try:
        bindings = [(a, load_controller("improved")) for a in conn.adapters.values()]
        world = conn.world
        spent = [0.0, 0.0, 0.0]
        clock = time.process_time
        for k in range(20 + cycles):
            t0 = clock()
            for adapter, _ in bindings:
                adapter.sense_all()
            t1 = clock()
            for adapter, controller in bindings:
                cmd = controller.tick(adapter.ns)
                adapter.command_wheels(cmd)
            t2 = clock()
            world.step()
            t3 = clock()
            if k >= 20:  # after the warm-up
                spent[0] += t1 - t0
                spent[1] += t2 - t1
                spent[2] += t3 - t2
    finally:
        conn.close()
    return {name: round(s / cycles / n * 1e6, 1) for name, s in zip(PHASES, spent)}
