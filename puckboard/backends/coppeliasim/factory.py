"""open_coppeliasim: the ``coppeliasim`` backend's factory, a scene's robots on one link.

Robot ``i`` of a scene drives the CoppeliaSim model copy CoppeliaSim would name for it
(``ePuck``, ``ePuck#0`` ...), so a scene file and a CoppeliaSim scene with that many
e-pucks fit together without configuration. All robots share one
:class:`~.link.RemoteLink` and one :class:`~.stepper.RemoteStepper`: one socket, one
``sim.step`` per cycle, however many robots there are.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import TYPE_CHECKING

from ...blackboard import Blackboard
from ...profile import get_profile
from ..base import Connection, RobotAdapter
from .adapter import EPuckVRep
from .link import DEFAULT_PORT, RemoteLink
from .stepper import RemoteStepper

if TYPE_CHECKING:
    from ...scenario.scene import Scene

__all__ = ["open_coppeliasim"]

log = logging.getLogger(__name__)


def open_coppeliasim(
    scene: Scene | str,
    *,
    seed: int = 0,
    host: str = "127.0.0.1",
    port: int = DEFAULT_PORT,
    timeout: float = 5.0,
    robots: Sequence[str] | dict[str, str] | None = None,
    blackboard: Blackboard | None = None,
    stop_on_close: bool = True,
    command_timeout: float | None = None,
    sense_mode: str = "auto",
    heading_offset: float = 0.0,
) -> Connection:
    """Connect the scene's robots, in order, to the e-pucks of a running simulation.

    Robot ``i`` of ``scene`` drives the model ``ePuck`` (i = 0), ``ePuck#0`` (i = 1),
    ``ePuck#1`` ... unless ``robots`` names them (a list in scene order, or a mapping
    robot name → object name/alias path). All robots share one connection and one
    :class:`RemoteStepper`. ``seed`` is accepted for the common factory signature; the
    simulator's randomness is its own. On close the wheels are stopped, stepping is
    released and, with ``stop_on_close``, the simulation is stopped (which restores the
    scene, so the next run starts from the same poses); pass ``stop_on_close=False`` when
    others share the simulation.
    """
    if isinstance(scene, str):
        from ...scenario.scenefile import load_scene

        scene = load_scene(scene)
    names = [r.name for r in scene.robots]
    if robots is None:
        paths = ["ePuck" if i == 0 else f"ePuck#{i - 1}" for i in range(len(names))]
    elif isinstance(robots, dict):
        unknown = sorted(set(robots) - set(names))
        if unknown:
            raise ValueError(f"robots names {unknown} are not in scene {scene.name!r}: {names}")
        paths = [
            robots.get(n, "ePuck" if i == 0 else f"ePuck#{i - 1}") for i, n in enumerate(names)
        ]
    else:
        paths = list(robots)
        if len(paths) != len(names):
            raise ValueError(
                f"robots lists {len(paths)} objects for the {len(names)} robots of scene "
                f"{scene.name!r} ({names})"
            )
    log.debug("open_coppeliasim: seed %d is not used by a remote simulator", seed)
    link = RemoteLink(host, port, timeout)
    stepper = RemoteStepper(link, dt=None)
    board = blackboard if blackboard is not None else Blackboard(clock=lambda: stepper.time)
    adapters: dict[str, RobotAdapter] = {}
    try:
        for spec, path in zip(scene.robots, paths):
            adapters[spec.name] = EPuckVRep(
                spec.name,
                object_path=path,
                link=link,
                stepper=stepper,
                profile=get_profile(spec.profile),
                blackboard=board,
                command_timeout=command_timeout,
                sense_mode=sense_mode,
                heading_offset=heading_offset,
            )
    except BaseException:
        link.close()
        raise
    sim_dt = stepper.dt
    if abs(sim_dt - scene.dt) > 1e-9:
        log.warning(
            "the simulation's time step is %.4g s but scene %r asks for %.4g s; the control "
            "loop follows the simulation",
            sim_dt, scene.name, scene.dt,
        )  # fmt: skip
    log.info(
        "connected to %s: %s",
        link.endpoint,
        ", ".join(f"{n} → {p}" for n, p in zip(names, paths)),
    )
    return Connection(
        adapters=adapters,
        blackboard=board,
        stepper=stepper,
        world=None,
        extra_close=[lambda: stepper.release(stop=stop_on_close), link.close],
    )
