"""What a served world shows to a watcher, read-only and typed.

A viewer of ``puckboard serve`` (the web page) needs the served world's state, the
robots' model names, whether the simulation runs, the wheel targets the clients set, the
string signals they publish and who drives which robot. Those live in the server's
internals (the ``sim.*`` state, the world, the object tree, the client table), which
change as the served functions grow; a viewer reaching into them would be coupled to them
where no import and no type shows it. :class:`ServedView` is the one face they read
instead: each property names what it gives, and nothing here lets a viewer change the
simulation. The world itself is not handed out: :meth:`ServedView.step` gives a frozen
:class:`ServedStep` (time, poses, collisions, sensor readings), copied at the step it
was read, so a viewer neither sees the engine's live arrays change under it nor needs
to know the engine's types.

Like a step observer, a view is read in the server's thread (between requests), so it
reads without a lock; it copies nothing it is not asked for.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from ....scenario.scene import Scene
    from ....sim.world import World
    from .clients import ClientTable
    from .simapi import SimApi

__all__ = ["ServedClient", "ServedStep", "ServedView"]


@dataclass(frozen=True)
class ServedStep:
    """The served world at one step, as a viewer sees it: copies, read only, so it stays
    what it was when read. One row per robot, in the world's robot order."""

    #: The served run it belongs to: 0 for the first, one more after each restore of the
    #: scene (``sim.stopSimulation``), so a viewer sees where one run ends.
    run: int
    #: Simulation time (s) and steps taken since the run began.
    time: float
    step_count: int
    #: N×3 x (m), y (m), theta (rad).
    poses: np.ndarray
    #: N collisions counted so far (the judge's count).
    collisions: np.ndarray
    #: N×8 IR distances ps0..ps7 (m; ``prox_range`` of that robot: nothing seen).
    prox_distance: np.ndarray
    #: The distance that means "nothing seen", per robot (m).
    prox_range: tuple[float, ...]
    #: N×3 ground values gs0..gs2 (0 black .. 1 white).
    ground: np.ndarray
    #: N×2 wheel speeds left, right (rad/s).
    wheel_speeds: np.ndarray


def _frozen(values: np.ndarray) -> np.ndarray:
    out = np.array(values)
    out.flags.writeable = False
    return out


@dataclass(frozen=True)
class ServedClient:
    """One connected client, as a viewer sees it."""

    #: The first characters of its ``uuid`` (what the server's log says).
    short: str
    #: The robots whose wheels it commanded.
    robots: frozenset[int]
    #: It steps the simulation (``sim.setStepping``).
    stepping: bool
    #: A step's answer is held for it: it waits for the simulation, it is not idle.
    waiting: bool
    #: When it last sent a request (``time.monotonic()``, s).
    last_seen: float


class ServedView:
    """A read-only view of what a server serves (its ``sim.*`` state ``api`` and its
    ``clients``); see the module docstring. ``RemoteApiServer.view()`` makes one."""

    def __init__(self, api: SimApi, clients: ClientTable) -> None:
        self._api = api
        self._clients = clients
        self._model_names = tuple(b.name for b in api.objects.bases)
        self._world: World = api.world
        self._run = 0

    def step(self) -> ServedStep:
        """The served world now, frozen. ``sim.stopSimulation`` replaces the world with
        the restored scene: the step read after it belongs to the next ``run``."""
        world = self._api.world
        if world is not self._world:
            self._world = world
            self._run += 1
        return ServedStep(
            run=self._run,
            time=float(world.time),
            step_count=int(world.step_count),
            poses=_frozen(world.poses),
            collisions=_frozen(world.collisions),
            prox_distance=_frozen(world.prox_distance),
            prox_range=tuple(float(p.prox_range) for p in world.profiles),
            ground=_frozen(world.ground),
            wheel_speeds=_frozen(world.wheel_speeds),
        )

    @property
    def scene(self) -> Scene:
        return self._api.world.scene

    @property
    def model_names(self) -> tuple[str, ...]:
        """Each robot's model name (``ePuck#0``, …), in the world's robot order."""
        return self._model_names

    @property
    def running(self) -> bool:
        return bool(self._api.running)

    @property
    def paused(self) -> bool:
        return bool(self._api.paused)

    @property
    def targets(self) -> np.ndarray:
        """Wheel target velocities the clients set (rad/s), one row per robot (a copy)."""
        return np.array(self._api.targets)

    def signal(self, name: str) -> str | None:
        """The string signal ``name`` as text (a client may set bytes), or ``None``."""
        value = self._api.signals.string.get(name)
        if isinstance(value, bytes):
            return value.decode("utf-8", "replace")
        return value if isinstance(value, str) else None

    def clients(self) -> list[ServedClient]:
        return [
            ServedClient(
                short=c.short,
                robots=frozenset(c.robots),
                stepping=c.stepping > 0,
                waiting=c.parked is not None,
                last_seen=c.last_seen,
            )
            for c in self._clients
        ]
