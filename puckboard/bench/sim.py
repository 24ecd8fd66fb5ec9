"""The ``sim`` suite: the two-robot pass on the full stack, and where a step's time goes.

Whole control cycles (sensing, arbitration, physics) are timed through the control loop,
then the same cycle by hand, phase by phase, on the wall clock and in CPU time — the CPU
figures barely move when other programs share the machine — and the camera per frame.
Every repeat builds a fresh stack, so no repeat inherits another's state.
"""

from __future__ import annotations

import logging
import math
import os
import statistics
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from .timing import REPEATS, seconds_per_call

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["run_suite"]

log = logging.getLogger(__name__)


def _median_us(fn: Callable[[], Any], calls: int) -> float:
    return seconds_per_call(fn, calls) * 1e6


def _bench_scene() -> Any:
    try:
        from ..scenario.scenefile import load_scene

        return load_scene("two-robot-pass")
    except (ImportError, ValueError, OSError) as exc:
        log.warning("two-robot-pass not available (%s); using a small built-in scene", exc)
    import numpy as np

    from ..scenario.scene import CircleObstacle, RobotSpec, Scene, Track

    a = np.linspace(0.0, 2 * math.pi, 120, endpoint=False)
    track = Track(np.column_stack([0.6 * np.cos(a), 0.35 * np.sin(a)]), width=0.02)
    return Scene(
        "two-robot-pass (built-in)",
        robots=(
            RobotSpec("left", -0.6, 0.0, math.pi / 2),
            RobotSpec("right", 0.6, 0.0, -math.pi / 2, colour=(40, 60, 200)),
        ),
        track=track,
        obstacles=(CircleObstacle(0.0, 0.35, 0.025), CircleObstacle(0.0, -0.35, 0.025)),
    )


def _build_stack(scene: Scene, seed: int = 0) -> tuple[Any, Any]:
    from ..backends.embedded import EmbeddedAdapter
    from ..behaviours import load_controller
    from ..blackboard import Blackboard
    from ..control.loop import ControlLoop
    from ..sim.world import World

    world = World(scene, seed=seed)
    board = Blackboard(clock=lambda: world.time)
    bindings = []
    for i, spec in enumerate(scene.robots):
        adapter = EmbeddedAdapter(world, i, blackboard=board)
        bindings.append((adapter, load_controller(spec.controller or "improved")))
    return world, ControlLoop(bindings)


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """The two-robot pass, full stack, camera off: speed and where each step's time goes."""
    from ..records import CameraImage

    scene = _bench_scene()
    n_steps = steps or 2000
    dt = scene.dt
    out: dict[str, Any] = {
        "scene": scene.name,
        "robots": len(scene.robots),
        "dt_s": dt,
        "steps_per_repeat": n_steps,
        "repeats": REPEATS,
    }

    # whole cycles through ControlLoop, fresh stack each repeat
    rates = []
    cpu_rates = []
    for _ in range(REPEATS):
        world, loop = _build_stack(scene)
        for _ in range(20):
            loop.cycle()
        t0 = time.perf_counter()
        c0 = time.process_time()
        for _ in range(n_steps):
            loop.cycle()
        rates.append(n_steps / (time.perf_counter() - t0))
        cpu_rates.append(n_steps / max(time.process_time() - c0, 1e-9))
        loop.close()
    rate = statistics.median(rates)
    out["steps_per_s"] = rate
    out["steps_per_s_min_max"] = [min(rates), max(rates)]
    out["realtime_factor"] = rate * dt
    out["us_per_step"] = 1e6 / rate
    # per second of this process's CPU time: less sensitive to other work on the machine
    out["steps_per_cpu_s"] = statistics.median(cpu_rates)
    out["load_average_1min"] = _load_average()

    # the same cycle by hand, timing each phase on the wall clock and in CPU time (the
    # CPU figures barely move when other programs share the machine)
    phases = ("sensing", "arbitration", "physics")
    wall: dict[str, list[float]] = {p: [] for p in phases}
    cpu: dict[str, list[float]] = {p: [] for p in phases}
    models = []
    for _ in range(REPEATS):
        world, loop = _build_stack(scene)
        bindings = loop.bindings
        for _ in range(20):
            loop.cycle()
        w_acc = [0.0, 0.0, 0.0]
        c_acc = [0.0, 0.0, 0.0]
        clock = time.perf_counter
        cpu_clock = time.process_time
        for _ in range(n_steps):
            t0, c0 = clock(), cpu_clock()
            for b in bindings:
                b.adapter.sense_all()
            t1, c1 = clock(), cpu_clock()
            for b in bindings:
                cmd = b.controller.tick(b.adapter.ns)
                b.adapter.command_wheels(cmd)
            t2, c2 = clock(), cpu_clock()
            world.step()
            t3, c3 = clock(), cpu_clock()
            w_acc[0] += t1 - t0
            w_acc[1] += t2 - t1
            w_acc[2] += t3 - t2
            c_acc[0] += c1 - c0
            c_acc[1] += c2 - c1
            c_acc[2] += c3 - c2
        for k, phase in enumerate(phases):
            wall[phase].append(w_acc[k] / n_steps * 1e6)
            cpu[phase].append(c_acc[k] / n_steps * 1e6)
        models.append(world.sensor_seconds / world.step_count * 1e6)
        loop.close()
    labels = {
        "sensing": "sensing (adapter records + blackboard)",
        "arbitration": "arbitration (py_trees tick + wheel command)",
        "physics": "physics (world.step: kinematics, contacts, sensor models)",
    }
    out["cost_us_per_step"] = {labels[p]: statistics.median(wall[p]) for p in phases}
    out["cost_us_per_step"]["  of which sensor models (IR rays, ground)"] = statistics.median(
        models
    )  # averaged over the whole run, warm-up included
    out["cpu_us_per_step"] = {labels[p]: statistics.median(cpu[p]) for p in phases}

    # camera, per frame, one robot
    world, loop = _build_stack(scene)
    width, height = scene.camera_size
    out["camera_size"] = [width, height]
    frames = min(300, max(20, n_steps // 5))
    out["camera_us_per_frame"] = _median_us(
        lambda: CameraImage(pixels=world.render_camera(0)), frames
    )
    big = (160, 120)
    out["camera_160x120_us_per_frame"] = _median_us(
        lambda: CameraImage(pixels=world.render_camera(0, big)), frames
    )
    loop.close()
    return out


def _load_average() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):  # not available on Windows
        return None
