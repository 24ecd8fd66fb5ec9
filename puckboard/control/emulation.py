"""A scene run around one emulated e-puck: the client drives it over the robot's own wire.

The wire itself (the emulated robot, its protocols, the servers) is the e-puck backend's
(:mod:`puckboard.backends.epuck.emulator`); this module is the episode around it, which
needs controllers and a judge and so belongs with the control loop. :class:`Emulation`
builds a :class:`~puckboard.sim.world.World` for a scene, serves its first robot over the
e-puck2 Wi-Fi protocol (TCP) or advanced sercom (a pseudo-terminal on POSIX, or TCP for
pyserial's ``socket://`` URLs), and steps the world in real time like a robot: one step
of ``dt`` per ``dt`` of wall-clock time, the wheels turning at the last commanded speeds.
The judge watches the ground-truth poses, and :meth:`run` returns its verdict as an
:class:`~puckboard.scenario.result.EpisodeResult`, the same fields as ``puckboard run
--json``.

The clock starts with the first command a client sends (the moment a real robot would
start moving), so a slow connect does not count against the controller. The run ends
when the client is done: it disconnects (TCP), or sends nothing for ``idle_timeout``
seconds (a pseudo-terminal cannot tell a closed client from a silent one), or at the
latest after ``duration``. When the client disconnects the wheels stop. The scene's
other robots (the oncoming robot of the two-robot pass, say) are driven by their own
scene controllers inside the emulator, synchronously with the world, unless
``others="still"`` leaves them standing.

With ``link`` (a link of :mod:`puckboard.profile.links`, e.g. ``"bluetooth-sercom"``)
every reply is held back by a latency drawn within that link's range, so a client on
this machine runs at that link's pace and ``puckboard calibrate link`` measures it.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from ..backends.epuck.emulator.endpoint import PROTOCOLS, open_endpoint
from ..backends.epuck.emulator.robot import EmulatedRobot
from ..profile import RobotProfile
from ..profile.links import LinkTiming, get_link
from ..scenario.judge import Judge
from ..scenario.scene import Scene

__all__ = ["START_SLACK", "Emulation"]

log = logging.getLogger(__name__)

START_SLACK = 10.0
"""Seconds added to the scene's duration by default (connecting, building controllers)."""


class Emulation:
    """Emulate the first robot of ``scene``; see the module docstring.

    ``protocol`` is ``"wifi"`` or ``"sercom"``; ``port`` is the TCP port (``0``: any free
    one). For sercom, ``serial="pty"`` (POSIX) or ``"tcp"`` chooses the carrier. The
    emulator stands in for the physical robot, so every robot is given the ``epuck``
    profile unless ``profile`` names another, shipped or a profile file (``None`` keeps
    the scene's). ``link`` holds every reply back by that link's latency (see the
    module docstring).
    """

    def __init__(
        self,
        scene: Scene | str,
        *,
        protocol: str = "wifi",
        host: str = "127.0.0.1",
        port: int = 0,
        seed: int = 0,
        serial: str | None = None,
        realtime: float = 1.0,
        others: str = "controller",
        until_client_leaves: bool = True,
        idle_timeout: float | None = 2.0,
        profile: str | RobotProfile | None = "epuck",
        link: str | LinkTiming | None = None,
    ) -> None:
        from ..sim.world import World

        if protocol not in PROTOCOLS:
            raise ValueError(f"protocol must be one of {', '.join(PROTOCOLS)}, got {protocol!r}")
        if others not in ("controller", "still"):
            raise ValueError(f"others must be 'controller' or 'still', got {others!r}")
        if realtime <= 0:
            raise ValueError(f"realtime factor must be positive, got {realtime}")
        if isinstance(scene, str):
            from ..scenario.scenefile import load_scene

            scene = load_scene(scene)
        from ..scenario.conversion import for_seed

        scene = for_seed(scene, seed)  # a generated scene's track for this seed
        if profile is not None:  # it stands in for the physical robot
            from ..scenario.robot_profiles import scene_profile

            scene = scene.with_profile(scene_profile(profile))
        self.scene = scene
        self.protocol = protocol
        self.seed = seed
        self.realtime = realtime
        self.world = World(scene, seed=seed)
        self.robot = EmulatedRobot(self.world, 0, selector=15 if protocol == "wifi" else 3)
        self.judge = Judge(scene)
        self._others = self._build_others() if others == "controller" else []
        self.judge.update(self.world.time, self.world.poses, self.world.collisions)
        self._lock = self.robot.lock
        self._stop = threading.Event()
        self._client_left = threading.Event()
        self.until_client_leaves = until_client_leaves
        self.idle_timeout = idle_timeout
        self.ended_by = ""
        self._started_at: float | None = None
        self.wall_s = 0.0
        self.server, self.info = open_endpoint(
            self.robot, protocol, self._client_gone, host=host, port=port, serial=serial
        )
        #: the link whose latency every reply is held back by (None: answered at once)
        self.link = None if link is None else get_link(link) if isinstance(link, str) else link
        if self.link is not None:
            self.server.reply_delay = _link_delay(self.link, seed, realtime)

    def _client_gone(self) -> None:
        self.robot.stop()
        if self.robot.commands:
            self._client_left.set()

    def _build_others(self) -> list[tuple[Any, Any]]:
        """An embedded adapter and the scene's controller for every robot but the first."""
        if len(self.scene.robots) < 2:
            return []
        from ..backends.embedded import EmbeddedAdapter
        from ..behaviours import load_controller
        from ..blackboard import Blackboard

        world = self.world
        board = Blackboard(clock=lambda: world.time)
        out = []
        for i, spec in enumerate(self.scene.robots[1:], start=1):
            adapter = EmbeddedAdapter(world, i, blackboard=board)
            out.append((adapter, load_controller(spec.controller)))
        return out

    def _drive_others(self) -> None:
        for adapter, controller in self._others:
            adapter.sense_all()
            cmd = controller.tick(adapter.ns)
            adapter.command_wheels(cmd)

    # -- running ---------------------------------------------------------------------------
    def start(self) -> None:
        """Start serving (the world waits for the first command)."""
        self.server.start()

    def stop(self) -> None:
        """Ask :meth:`run` to return (thread-safe; also from a signal-free UI thread)."""
        self._stop.set()

    def close(self) -> None:
        self._stop.set()
        self.robot.stop()
        self.server.stop()
        with self._lock:
            for adapter, _ in self._others:
                adapter.close()

    def run(self, duration: float | None = None, *, wait_for_client: float | None = None) -> Any:
        """Serve and step in real time for at most ``duration`` s of robot time, counted
        from the first command (default: the scene's duration plus :data:`START_SLACK`, as a
        client's own run starts a moment after its first command); returns the judge's
        verdict as an :class:`~puckboard.scenario.result.EpisodeResult`. Returns early when the
        client is done (see the module docstring), after :meth:`stop`, or when no client
        sent a command within ``wait_for_client`` seconds."""
        duration = self.scene.duration + START_SLACK if duration is None else float(duration)
        if duration <= 0:
            raise ValueError(f"duration must be positive seconds, got {duration}")
        if not self.server.started:
            self.start()
        t_open = time.monotonic()
        try:
            while self.robot.commands == 0 and not self._stop.is_set():
                if wait_for_client is not None and time.monotonic() - t_open > wait_for_client:
                    log.warning("no client sent a command within %.1f s", wait_for_client)
                    return self.result()
                self._check_server()
                self._stop.wait(0.01)
            self._pace(duration)
        except KeyboardInterrupt:
            self.ended_by = "interrupted"  # not the duration, whatever the loop was at
            raise
        finally:
            self.close()
        return self.result()

    def _pace(self, duration: float) -> None:
        dt = self.world.dt
        period = dt / self.realtime
        steps = int(round(duration / dt))
        t0 = time.monotonic()
        self._started_at = t0
        self.ended_by = "duration"
        for k in range(1, steps + 1):
            if self._stop.is_set():
                self.ended_by = "stopped"
                break
            if self.until_client_leaves and self._client_left.is_set():
                self.ended_by = "client left"
                break
            idle = time.monotonic() - self.robot.last_command
            if self.idle_timeout is not None and idle > self.idle_timeout:
                self.ended_by = f"client silent for {self.idle_timeout:g} s"
                break
            self._check_server()
            delay = t0 + k * period - time.monotonic()
            if delay > 0 and self._stop.wait(delay):
                break
            with self._lock:
                self._drive_others()
                self.world.step(1)
                self.judge.update(self.world.time, self.world.poses, self.world.collisions)
            self.wall_s = time.monotonic() - t0

    def _check_server(self) -> None:
        if self.server.error is not None:
            raise RuntimeError(
                f"the emulator's server failed: {self.server.error}"
            ) from self.server.error

    def result(self) -> Any:
        """The judge's verdict so far, as an :class:`~puckboard.scenario.result.EpisodeResult`."""
        from ..scenario.result import EpisodeResult

        with self._lock:
            self.judge.finish()
            return EpisodeResult(
                scenario=self.scene.name,
                controller=f"external ({self.info.backend})",
                seed=self.seed,
                dt_s=self.world.dt,
                steps=int(self.world.step_count),
                sim_time_s=float(self.world.time),
                wall_s=float(self.wall_s),
                success=bool(self.judge.success),
                failure=self.judge.failure,
                failures=list(self.judge.failures),
                robots=self.judge.metrics(),
                events=list(self.judge.events),
            )

    def __enter__(self) -> Emulation:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _link_delay(link: LinkTiming, seed: int, realtime: float) -> Callable[[], float]:
    """Each reply's delay (s): drawn uniformly within ``link``'s latency range, from a
    generator of its own (the world's draws stay the same with or without a link), and
    shortened as the emulator is sped up."""
    rng = np.random.Generator(np.random.PCG64([int(seed), 0x11CC]))
    low, high = link.latency

    def delay() -> float:
        return (low + float(rng.random()) * (high - low)) / realtime

    return delay
