"""The ``floor`` suite: the two-robot pass's full stack next to its floor, in one run.

Every answer puckboard gives is a number of episodes, and an episode a number of control
cycles. A cycle's *floor* is what its design cannot do without: one engine step of both
robots (:meth:`~puckboard.sim.world.World.step`: motion, contacts, every sensor model)
and two bare py_trees Selector ticks, one per robot (:mod:`.bare_tree`: four behaviours
reading a py_trees blackboard, nothing of puckboard's). The *full stack* is what
:class:`~puckboard.control.episode.Episode` does per cycle: sense (records onto the
blackboard), tick both controllers, command the wheels, step the world and judge the
step. ``ratio`` is full stack over floor, the figure to quote.

The engine is timed on the very trajectory the full stack drove: one untimed run of the
episode records the wheel speeds of every cycle, and a fresh world of the same scene
and seed replays them with nothing else running (``engine_replay_identical`` says the
replay ended in the same poses, bit for bit). The three are measured in turns, each
repeat once, so a change of the machine's load touches all three; medians of
:data:`~puckboard.bench.timing.REPEATS` repeats of ``steps`` cycles after 20 warm-up
cycles, on the wall clock and in CPU time (``time.process_time``, which other programs
on the machine disturb much less).

``split_cpu_us`` times the same cycle by hand, part by part (CPU µs per cycle, both
robots), to show where the stack's time beyond the floor goes.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from typing import Any

from .bare_tree import bare_selector
from .timing import REPEATS

__all__ = ["CONTROLLERS", "SCENE", "run_suite"]

#: The scene and the controllers the floor is measured on.
SCENE = "two-robot-pass"
CONTROLLERS = ("improved", "robust")
#: Cycles run before timing starts.
WARMUP = 20


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Full stack, engine step and bare ticks of the two-robot pass, and their ratio."""
    import py_trees

    n = steps or 2000
    out: dict[str, Any] = {
        "scene": SCENE,
        "steps_per_repeat": n,
        "repeats": REPEATS,
        "floor": "engine step + 2 bare py_trees Selector ticks",
    }
    tick = bare_selector()
    try:
        for controller in CONTROLLERS:
            out[controller] = _measure(controller, n, tick)
    finally:
        py_trees.blackboard.Blackboard.clear()
    return out


def _episode(controller: str) -> Any:
    from ..control.episode import Episode

    return Episode(SCENE, controller=controller, seed=0)


def _measure(controller: str, n: int, bare_tick: Callable[[], None]) -> dict[str, Any]:
    import numpy as np

    commands, final_poses, scene = _recorded(controller, n)
    wall: dict[str, list[float]] = {"full": [], "engine": [], "bare": []}
    cpu: dict[str, list[float]] = {"full": [], "engine": [], "bare": []}
    split: dict[str, list[float]] = {}
    identical = True
    for _ in range(REPEATS):
        w, c = _full_stack(controller, n)
        wall["full"].append(w)
        cpu["full"].append(c)
        w, c, poses = _engine(scene, commands)
        wall["engine"].append(w)
        cpu["engine"].append(c)
        identical = identical and bool(np.array_equal(poses, final_poses))
        w, c = _timed(bare_tick, WARMUP, n)
        wall["bare"].append(w)
        cpu["bare"].append(c)
        for part, us in _split(controller, n).items():
            split.setdefault(part, []).append(us)
    res: dict[str, Any] = {}
    for clock, samples, suffix in ((wall, wall, "us"), (cpu, cpu, "cpu_us")):
        full = statistics.median(samples["full"])
        engine = statistics.median(samples["engine"])
        bare = statistics.median(samples["bare"])
        floor = engine + 2 * bare
        res[f"full_stack_{suffix}"] = full
        res[f"engine_step_{suffix}"] = engine
        res[f"bare_tick_{suffix}"] = bare
        res[f"floor_{suffix}"] = floor
        res["ratio" if clock is wall else "ratio_cpu"] = round(full / floor, 2)
    res["engine_replay_identical"] = identical
    res["split_cpu_us"] = {part: statistics.median(v) for part, v in split.items()}
    return res


def _recorded(controller: str, n: int) -> tuple[list[list[list[float]]], Any, Any]:
    """One untimed run of the episode: the wheel speeds of every cycle, the final poses
    and the scene the episode built (its world's, for the replay)."""
    episode = _episode(controller)
    world, loop = episode.world, episode.loop
    if episode.scene.control.steps(world.dt)[1]:
        raise ValueError(f"{SCENE}: the replay needs a scene without control latency")
    commands = []
    for _ in range(WARMUP + n):
        loop.cycle()
        commands.append(world.wheel_speeds.tolist())
    poses = world.poses.copy()
    loop.close()
    return commands, poses, episode.scene


def _full_stack(controller: str, n: int) -> tuple[float, float]:
    """Wall and CPU µs per cycle of an episode's control loop (its judge included)."""
    episode = _episode(controller)
    loop = episode.loop
    try:
        return _timed(loop.cycle, WARMUP, n)
    finally:
        loop.close()


def _engine(scene: Any, commands: list[list[list[float]]]) -> tuple[float, float, Any]:
    """Wall and CPU µs per step of a fresh world replaying ``commands``, and its final
    poses (the run's own, when the replay is exact)."""
    from ..sim.world import World

    world = World(scene, seed=0)
    world.start()
    drive, step = world.drive, world.step
    robots = range(world.n)
    for wheels in commands[:WARMUP]:
        for i in robots:
            drive(i, *wheels[i])
        step()
    wall = cpu = 0.0
    clock, cpu_clock = time.perf_counter, time.process_time
    for wheels in commands[WARMUP:]:
        for i in robots:
            drive(i, *wheels[i])
        t0, c0 = clock(), cpu_clock()
        step()
        wall += clock() - t0
        cpu += cpu_clock() - c0
    n = len(commands) - WARMUP
    return wall / n * 1e6, cpu / n * 1e6, world.poses.copy()


def _timed(fn: Callable[[], Any], warmup: int, n: int) -> tuple[float, float]:
    """Wall and CPU µs per call of ``n`` calls to ``fn`` after ``warmup`` calls."""
    for _ in range(warmup):
        fn()
    t0, c0 = time.perf_counter(), time.process_time()
    for _ in range(n):
        fn()
    return (time.perf_counter() - t0) / n * 1e6, (time.process_time() - c0) / n * 1e6


def _split(controller: str, n: int) -> dict[str, float]:
    """CPU µs per cycle of each part of the cycle, run by hand as the loop runs it."""
    episode = _episode(controller)
    loop = episode.loop
    bindings, steppers = loop.bindings, loop.steppers
    for _ in range(WARMUP):
        loop.cycle()
    parts = ("sensing", "ticks", "commands", "engine", "judge")
    acc = dict.fromkeys(parts, 0.0)
    clock = time.process_time
    try:
        for _ in range(n):
            t0 = clock()
            for b in bindings:
                b.adapter.sense_all()
            for callback in loop.before_tick:
                callback(loop)
            t1 = clock()
            commands = [b.controller.tick(b.adapter.ns) for b in bindings]
            t2 = clock()
            for b, cmd in zip(bindings, commands):
                b.adapter.command_wheels(cmd)
            t3 = clock()
            for stepper in steppers:
                stepper.step(loop.steps_per_cycle)
            t4 = clock()
            loop.cycles += 1
            for observer in loop.observers:
                observer(loop)
            t5 = clock()
            acc["sensing"] += t1 - t0
            acc["ticks"] += t2 - t1
            acc["commands"] += t3 - t2
            acc["engine"] += t4 - t3
            acc["judge"] += t5 - t4
    finally:
        loop.close()
    return {part: acc[part] / n * 1e6 for part in parts}
