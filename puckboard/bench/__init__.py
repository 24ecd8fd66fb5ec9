"""Benchmarks: how fast the blackboard, the arbiter and the embedded simulator run.

``puckboard bench`` runs the suites in :data:`SUITES`. A suite is a function
``run_suite(steps: int | None) -> dict`` named as ``"module:function"`` so that other
parts of puckboard (or a user's package) can add their own; a suite whose module, or an
optional package it needs, is not installed is skipped with a note naming the extra to
install, not an error.

Every figure is the median over several repeats after a warm-up, timed with
``time.perf_counter``; results carry the number of repeats and the machine so they can be
compared honestly. Benchmarks are never pass/fail tests.
"""

from __future__ import annotations

import inspect
import logging
import math
import os
import pkgutil
import platform
import statistics
import time
from collections.abc import Callable, Mapping
from typing import Any

from .._extras import extra_for, missing_package_message
from .timing import REPEATS, seconds_per_call

__all__ = ["SUITES", "machine", "run_suites", "sim_suite"]

log = logging.getLogger(__name__)

#: Suite name → ``"module:function"``; the function takes ``steps`` (or None for its
#: default) and returns a dict of results.
SUITES: dict[str, str] = {
    "core": "puckboard.bench:core_suite",
    "sim": "puckboard.bench:sim_suite",
    "coppeliasim": "puckboard.bench.coppeliasim:run_suite",
    "sweep": "puckboard.bench.sweep:run_suite",
    "estimation": "puckboard.bench.estimation:run_suite",
    "emulator": "puckboard.bench.emulator:run_suite",
    "scale": "puckboard.bench.scale:run_suite",
    "web": "puckboard.bench.web:run_suite",
    "compare": "puckboard.bench.compare:run_suite",
}

#: Suites run when none is named.
DEFAULT_SUITES: tuple[str, ...] = ("core", "sim")


def machine() -> dict[str, Any]:
    """What the figures were measured on."""
    import numpy as np

    return {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "platform": platform.platform(terse=True),
        "processor": platform.processor() or platform.machine(),
        "cpus": os.cpu_count(),
    }


def resolve_suite(name: str) -> Callable[..., dict[str, Any]]:
    """The function behind suite ``name``; ImportError if its module is missing."""
    try:
        target = SUITES[name]
    except KeyError:
        raise KeyError(f"unknown benchmark suite {name!r}; suites: {', '.join(SUITES)}") from None
    return pkgutil.resolve_name(target)  # type: ignore[no-any-return]


def suite_options(name: str) -> set[str]:
    """The keyword options suite ``name`` accepts beyond ``steps`` (empty if not importable)."""
    try:
        return _keywords(resolve_suite(name))
    except (ImportError, AttributeError):
        return set()


def _keywords(fn: Callable[..., Any]) -> set[str]:
    """The keyword options a suite function takes beyond ``steps``."""
    params = inspect.signature(fn).parameters.values()
    return {p.name for p in params if p.name != "steps" and p.kind is not p.VAR_KEYWORD}


def run_suites(
    names: list[str], steps: int | None = None, options: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """Run the named suites; a suite whose module is absent gets ``{"skipped": reason}``.

    So does a suite that needs one of puckboard's optional packages (the coppeliasim
    suite imports pyzmq only when it starts its server): the reason names the extra
    that installs it. Any other ImportError is a bug and propagates.

    ``options`` are keyword arguments for the suites (e.g. ``seeds`` for ``estimation``);
    each suite receives those it accepts, so one command line can serve several suites.
    """
    results: dict[str, Any] = {"machine": machine(), "suites": {}}
    for name in names:
        try:
            fn = resolve_suite(name)
        except ImportError as exc:
            results["suites"][name] = {"skipped": _missing(name, exc)}
            continue
        except AttributeError as exc:
            results["suites"][name] = {"skipped": f"suite function not available ({exc})"}
            continue
        accepted = _keywords(fn)
        kwargs = {k: v for k, v in (options or {}).items() if k in accepted}
        try:
            results["suites"][name] = fn(steps, **kwargs)
        except ImportError as exc:
            if extra_for(exc) is None:
                raise
            results["suites"][name] = {"skipped": _missing(name, exc)}
        if "skipped" in results["suites"][name]:
            log.info("benchmark suite %r skipped: %s", name, results["suites"][name]["skipped"])
    return results


def _missing(name: str, exc: ImportError) -> str:
    """Why suite ``name`` cannot run: the extra to install when the missing module is one
    of puckboard's optional packages, else Python's own words (a user's suite)."""
    if extra_for(exc) is not None:
        return missing_package_message(f"suite {name!r}", exc)
    return f"module not available ({exc})"


def _median_us(fn: Callable[[], Any], calls: int) -> float:
    return seconds_per_call(fn, calls) * 1e6


# -- core: blackboard and arbiter next to py_trees ------------------------------------------
def core_suite(steps: int | None = None) -> dict[str, Any]:
    """Blackboard put+get and a 4-layer arbiter tick, each next to its py_trees equivalent."""
    import numpy as np
    import py_trees

    from ..backends.base import declare_robot_keys
    from ..behaviours import load_controller
    from ..blackboard import Blackboard
    from ..records import Ground, Pose, Proximity, Sensor

    calls = steps or 5000
    out: dict[str, Any] = {"calls_per_repeat": calls, "repeats": REPEATS}

    board = Blackboard()
    value = 1.0

    def bb_put_get() -> None:
        board.put("robot/x", value)
        board.get("robot/x")

    out["blackboard_put_get_us"] = _median_us(bb_put_get, calls)

    py_trees.blackboard.Blackboard.clear()
    client = py_trees.blackboard.Client(name="bench")
    client.register_key("x", access=py_trees.common.Access.WRITE)

    def pt_set_get() -> None:
        client.set("x", value)
        client.get("x")

    out["py_trees_client_set_get_us"] = _median_us(pt_set_get, calls)

    # the improved controller (4 layers) ticking on a namespace of fresh records
    board2 = Blackboard(clock=lambda: 0.0)
    ns = board2.namespace("epuck")
    declare_robot_keys(ns)
    prox = Proximity(np.array([0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05, 0.05]), np.zeros(8))
    ns.put_many(
        {
            Sensor.PROXIMITY.key: prox,
            Sensor.GROUND.key: Ground(np.array([0.9, 0.1, 0.9]), np.array([920.0, 100, 920])),
            Sensor.POSE.key: Pose(0.0, 0.0, 0.0),
        },
        stamp=0.0,
    )
    controller = load_controller("improved")
    out["arbiter_tick_us"] = _median_us(lambda: controller.tick(ns), calls)
    out["arbiter_layers"] = len(controller.layers)
    out["arbiter_active_layer"] = controller.active_layer

    # the same shape in plain py_trees: 4 children reading via a Client, writing a command
    py_trees.blackboard.Blackboard.clear()
    writer = py_trees.blackboard.Client(name="sensors")
    writer.register_key("ground", access=py_trees.common.Access.WRITE)
    writer.register_key("proximity", access=py_trees.common.Access.WRITE)
    writer.set("ground", (0.9, 0.1, 0.9))
    writer.set("proximity", tuple([0.05] * 8))

    class _Layer(py_trees.behaviour.Behaviour):
        def __init__(self, name: str, key: str, wants: Callable[[Any], bool]) -> None:
            super().__init__(name)
            self.key = key
            self.wants = wants
            self.bb = self.attach_blackboard_client(name=name)
            self.bb.register_key(key, access=py_trees.common.Access.READ)
            self.bb.register_key("cmd", access=py_trees.common.Access.WRITE)

        def update(self) -> py_trees.common.Status:
            reading = self.bb.get(self.key)
            if not self.wants(reading):
                return py_trees.common.Status.FAILURE
            self.bb.set("cmd", (1.0, 1.0))
            return py_trees.common.Status.RUNNING

    children = [
        _Layer("avoid", "proximity", lambda p: min(p[0], p[7]) < 0.05),
        _Layer("line", "ground", lambda g: min(g) < 0.5),
        _Layer("wall", "proximity", lambda p: p[2] < 0.05),
        _Layer("cruise", "ground", lambda g: True),
    ]
    root = py_trees.composites.Selector("arbiter", memory=False, children=children)
    tree = py_trees.trees.BehaviourTree(root)
    tree.setup()
    out["py_trees_selector_tick_us"] = _median_us(tree.tick, calls)
    py_trees.blackboard.Blackboard.clear()
    return out


# -- sim: the two-robot pass with the full stack --------------------------------------------
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


def _build_stack(scene: Any, seed: int = 0) -> tuple[Any, Any]:
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


def sim_suite(steps: int | None = None) -> dict[str, Any]:
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


# -- output ------------------------------------------------------------------------------
def format_results(results: dict[str, Any]) -> str:
    """A readable table of :func:`run_suites` results."""
    lines = []
    m = results.get("machine", {})
    lines.append(
        f"machine: {m.get('platform')} · {m.get('cpus')} CPUs · Python {m.get('python')} · "
        f"numpy {m.get('numpy')}"
    )
    for name, res in results.get("suites", {}).items():
        lines.append("")
        lines.append(f"[{name}]")
        if "skipped" in res:
            lines.append(f"  skipped: {res['skipped']}")
            continue
        _format_items(res, lines, indent="  ")
    return "\n".join(lines)


#: Longest list of records the table shows in full; ``--json`` always has everything.
TABLE_LIST_LIMIT = 8


def _format_items(res: dict[str, Any], lines: list[str], indent: str) -> None:
    width = max((len(str(k)) for k in res), default=0)
    for key, value in res.items():
        if isinstance(value, dict):
            lines.append(f"{indent}{key}:")
            _format_items(value, lines, indent + "  ")
        elif isinstance(value, (list, tuple)) and any(isinstance(v, dict) for v in value):
            lines.append(f"{indent}{key}: {len(value)} records")
            for k, item in enumerate(value[:TABLE_LIST_LIMIT]):
                lines.append(f"{indent}  [{k}]")
                if isinstance(item, dict):
                    _format_items(item, lines, indent + "    ")
                else:
                    lines.append(f"{indent}    {_fmt(item)}")
            if len(value) > TABLE_LIST_LIMIT:
                lines.append(f"{indent}  ... {len(value) - TABLE_LIST_LIMIT} more (see --json)")
        else:
            lines.append(f"{indent}{key:<{width}}  {_fmt(value)}")


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        if value == 0 or 0.01 <= abs(value) < 1e6:
            return f"{value:,.2f}"
        return f"{value:.3g}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    return str(value)
