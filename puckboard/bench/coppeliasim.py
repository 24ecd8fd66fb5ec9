"""The thesis's eight performance tests (§5.1.2), against ``puckboard serve`` on loopback.

The thesis timed its Java EPuckVRep against V-REP 3.x through the legacy remote API: one
``simxCallScriptFunction`` cost about 70 ms, so a loop that read the ground sensor and
set the motors took 140 ms, and reading everything with one ``simxGetStringSignal``
brought it to 72 ms (173 ms with the camera). Here the same eight loops run with
EPuckVRep over the ZeroMQ remote API against an in-process ``puckboard serve`` of the
line-follow scene (the thesis's Figure 5.1), and each loop also takes one synchronous
simulation step, which the thesis's real-time V-REP did not need:

== ===================================================== ===============================
01 ground by its own call                                 ``refresh("ground")``, one-call mode
02 ground from sense-all                                  ``sense_all()`` (one round trip)
03 pose and ground, each by its own calls                 ``refresh`` ×2, one-call mode
04 pose and ground from sense-all                         ``sense_all()``
05 sense-all in a sensing thread                          the loop only reads the blackboard
06 camera and sense-all, no threads                       ``camera_image()`` + ``sense_all()``
07 camera in a thread, sense-all in the loop
08 camera and sense-all each in a thread
== ===================================================== ===============================

Every loop also sets both wheels (two ``sim.setJointTargetVelocity`` calls) and steps
once. Two more rows give the headline: a **full control cycle** — every sensor, both
wheels, one step — with sense-all, and the same with one call per sensor object (the
naive path: 8 IR sensors, the light sensor, 4 joint reads, the pose).

Run it with ``puckboard bench --suite coppeliasim`` or ``python -m puckboard.bench.coppeliasim``.
It is a benchmark, never a test: the figures depend on the machine and its load.
"""

from __future__ import annotations

import importlib
import logging
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .timing import median_seconds

if TYPE_CHECKING:
    from ..backends.base import RobotAdapter

__all__ = ["THESIS", "format_table", "run_suite"]

log = logging.getLogger(__name__)

#: The thesis's averages (ms), §5.1.5: loop time, the sensor call(s), the motor call.
THESIS: dict[str, dict[str, float]] = {
    "01": {"loop": 139.94, "sense": 69.73, "wheels": 70.12},
    "02": {"loop": 67.96, "sense": 0.05, "wheels": 67.89},
    "03": {"loop": 205.86, "sense": 69.46 + 67.77, "wheels": 68.58},
    "04": {"loop": 72.71, "sense": 0.05, "wheels": 72.65},
    "05": {"loop": 71.11, "sense": 0.02, "wheels": 71.09},
    "06": {"loop": 173.34, "sense": 0.04, "camera": 77.39, "wheels": 95.89},
    "07": {"loop": 83.19, "sense": 0.01, "camera": 71.24, "wheels": 71.33},
    "08": {"loop": 83.37, "sense": 0.02, "camera": 71.46, "wheels": 83.36},
}

TITLES = {
    "01": "ground by its own call",
    "02": "ground from sense-all",
    "03": "pose + ground, own calls",
    "04": "pose + ground from sense-all",
    "05": "sense-all in a thread",
    "06": "camera + sense-all, no threads",
    "07": "camera thread, sense-all in loop",
    "08": "camera and sensing threads",
    "full": "full cycle, sense-all",
    "naive": "full cycle, one call per sensor",
}

SENSING_THREAD_PERIOD = 0.002  # s
CAMERA_THREAD_PERIOD = 0.01  # s
WARMUP = 20


@dataclass
class _Test:
    key: str
    sense_mode: str  # "script" or "calls"
    body: Callable[[Any, dict[str, list[float]]], None]
    sensing_thread: bool = False
    camera_thread: bool = False


def _timed(timings: dict[str, list[float]], what: str, fn: Callable[[], Any]) -> Any:
    t0 = time.perf_counter()
    value = fn()
    timings.setdefault(what, []).append(time.perf_counter() - t0)
    return value


def _drive(robot: RobotAdapter, timings: dict[str, list[float]]) -> None:
    """Decide from the ground sensor (a plain line follower) and set both wheels."""
    ground = robot.ns.snapshot(["ground"]).value("ground")
    left = right = 4.0
    if ground is not None:
        g = ground.value
        left, right = 4.0 + 3.0 * (g[0] - g[2]), 4.0 - 3.0 * (g[0] - g[2])
    _timed(timings, "wheels", lambda: robot.set_wheel_speeds(left, right))


def _body(*reads: str, camera: bool = False) -> Callable[[Any, dict[str, list[float]]], None]:
    from ..records import Sensor

    def body(robot: RobotAdapter, timings: dict[str, list[float]]) -> None:
        if camera:
            _timed(timings, "camera", robot.camera_image)
        if reads == ("all",):
            _timed(timings, "sense", robot.sense_all)
        elif reads:
            t0 = time.perf_counter()
            for name in reads:
                robot.refresh(Sensor(name))
            timings.setdefault("sense", []).append(time.perf_counter() - t0)
        _drive(robot, timings)
        _timed(timings, "step", robot.step)

    return body


def _tests() -> list[_Test]:
    return [
        _Test("01", "calls", _body("ground")),
        _Test("02", "script", _body("all")),
        _Test("03", "calls", _body("pose", "ground")),
        _Test("04", "script", _body("all")),
        _Test("05", "script", _body(), sensing_thread=True),
        _Test("06", "script", _body("all", camera=True)),
        _Test("07", "script", _body("all"), camera_thread=True),
        _Test("08", "script", _body(), sensing_thread=True, camera_thread=True),
        _Test("full", "script", _body("all")),
        _Test("naive", "calls", _body("all")),
    ]


def _run_test(test: _Test, port: int, cycles: int) -> dict[str, Any]:
    from ..backends.coppeliasim.adapter import EPuckVRep
    from ..records import Sensor

    robot = EPuckVRep("perf", object_path="ePuck", port=port, sense_mode=test.sense_mode)
    timings: dict[str, list[float]] = {}
    try:
        robot.start_simulation()
        if test.sensing_thread:
            robot.start_sensing_thread(SENSING_THREAD_PERIOD)
        if test.camera_thread:
            robot.enable(Sensor.CAMERA)
            robot.start_camera_thread(CAMERA_THREAD_PERIOD)
        for _ in range(WARMUP):
            test.body(robot, {})
        loops = []
        for _ in range(cycles):
            t0 = time.perf_counter()
            test.body(robot, timings)
            loops.append(time.perf_counter() - t0)
        robot.stop_threads()
        robot.stop_simulation()
    finally:
        robot.close()
    loops.sort()
    out: dict[str, Any] = {
        "loop_ms": _median_ms(loops),
        # the 10th percentile: what a cycle costs when the machine's load does not interfere
        "loop_p10_ms": round(loops[len(loops) // 10] * 1e3, 4),
    }
    for what in ("sense", "camera", "wheels", "step"):
        if what in timings:
            out[f"{what}_ms"] = _median_ms(timings[what])
    return out


def _median_ms(values: list[float]) -> float:
    return round(median_seconds(values) * 1e3, 4)


def run_suite(steps: int | None = None, *, server: str = "thread") -> dict[str, Any]:
    """Run the eight tests and the full-cycle pair; ``steps`` control cycles per test.

    ``server="thread"`` serves from a thread of this process (client and server share
    the interpreter); ``"process"`` starts ``puckboard serve`` as a separate process.
    """
    if server not in ("thread", "process"):
        raise ValueError(f"server must be 'thread' or 'process', got {server!r}")
    # Both sides need the coppeliasim extra: import them now, so a missing package is
    # an ImportError naming it (the suite is then skipped) rather than a server process
    # that dies before its banner.
    importlib.import_module("puckboard.backends.coppeliasim.server.socket_loop")
    importlib.import_module("coppeliasim_zmqremoteapi_client")
    cycles = steps or 300
    port, stop = _start_server(server)
    results: dict[str, Any] = {
        "setup": (
            "EPuckVRep → puckboard serve line-follow "
            f"({'in-process thread' if server == 'thread' else 'separate process'}), "
            f"loopback, {cycles} cycles per test, medians; every loop sets both wheels and "
            "takes one synchronous step"
        ),
        "cycles": cycles,
    }
    try:
        tests: dict[str, Any] = {}
        for test in _tests():
            row = _run_test(test, port, cycles)
            thesis = THESIS.get(test.key)
            if thesis is not None:
                row["thesis_loop_ms"] = thesis["loop"]
                row["speedup"] = round(thesis["loop"] / row["loop_ms"], 1)
            tests[_row_name(test.key)] = row
        results["tests"] = tests
    finally:
        stop()
    full = tests[_row_name("full")]["loop_ms"]
    naive = tests[_row_name("naive")]["loop_ms"]
    results["full_cycle_ms"] = full
    results["naive_cycle_ms"] = naive
    results["naive_over_full"] = round(naive / full, 2)
    results["goal_full_cycle_ms"] = 1.5
    return results


def _row_name(key: str) -> str:
    return TITLES[key] if key in ("full", "naive") else f"{key} {TITLES[key]}"


def _start_server(mode: str) -> tuple[int, Callable[[], None]]:
    if mode == "thread":
        from ..backends.coppeliasim.server.socket_loop import RemoteApiServer
        from ..scenario.scenefile import load_scene

        srv = RemoteApiServer(load_scene("line-follow"), host="127.0.0.1", port=0).start()
        return srv.port, srv.close
    import socket
    import subprocess

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    proc = subprocess.Popen(
        [sys.executable, "-m", "puckboard", "serve", "line-follow", "--port", str(port)],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    assert proc.stdout is not None
    banner = proc.stdout.readline()  # printed once the port is bound
    if f":{port}" not in banner:
        proc.kill()
        raise RuntimeError(f"puckboard serve did not start: {banner!r}")

    def stop() -> None:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:  # pragma: no cover
            proc.kill()
            proc.wait(10)
        if proc.stdout is not None:
            proc.stdout.close()

    return port, stop


def format_table(results: dict[str, Any]) -> str:
    """The results beside the thesis's figures, as a Markdown table."""
    lines = [
        "| test | loop ms (median) | loop ms (p10) | sense ms | camera ms | wheels ms | step ms "
        "| thesis loop ms | speed-up |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, row in results["tests"].items():

        def cell(key: str, row: dict[str, Any] = row) -> str:
            value = row.get(key)
            return "" if value is None else f"{value:.3f}" if value < 10 else f"{value:.1f}"

        lines.append(
            f"| {name} | {cell('loop_ms')} | {cell('loop_p10_ms')} | {cell('sense_ms')} | "
            f"{cell('camera_ms')} | "
            f"{cell('wheels_ms')} | {cell('step_ms')} | {cell('thesis_loop_ms')} | "
            f"{row.get('speedup', '')} |"
        )
    lines.append("")
    lines.append(
        f"full control cycle (sense-all, both wheels, one step): {results['full_cycle_ms']:.3f} ms "
        f"median; one call per sensor: {results['naive_cycle_ms']:.3f} ms "
        f"({results['naive_over_full']}× slower); goal ≤ {results['goal_full_cycle_ms']} ms. "
        "Medians of per-call timings; sense/camera/wheels/step are the medians of those calls."
    )
    return "\n".join(lines)
