"""Backend factories for the real robot: ``--backend epuck2-wifi`` and ``--backend sercom``.

Both follow the factory contract of :mod:`puckboard.backends.registry`
(``factory(scene, *, seed=0, **options) -> Connection``) and drive the *first* robot of
the scene: a scene describes the experiment (start pose for dead reckoning, robot name,
profile), the robot on the table is the one you connected to.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ...blackboard import Blackboard
from ...errors import ConnectionLostError
from ...profile import EPUCK1, EPUCK2, RobotProfile, get_profile
from ..base import Connection
from .adapter import EPuckReal
from .link import Link
from .sercom_link import SercomLink
from .transport import SerialTransport, TcpTransport
from .wifi_codec import DEFAULT_PORT
from .wifi_link import WifiLink

if TYPE_CHECKING:
    from ...scenario.scene import Scene

__all__ = ["EMULATOR_WIFI_PORT", "open_sercom", "open_wifi"]

#: The port ``puckboard emulate --protocol wifi`` listens on by default: the robot's own
#: port 1000 needs administrator rights to bind.
EMULATOR_WIFI_PORT = 10000
_THIS_MACHINE = frozenset({"127.0.0.1", "localhost", "::1"})

log = logging.getLogger(__name__)


def open_wifi(
    scene: Scene | str | Path | None = None,
    *,
    seed: int = 0,
    host: str | None = None,
    port: int | None = DEFAULT_PORT,
    timeout: float = 1.0,
    retries: int = 2,
    connect_timeout: float = 5.0,
    command_timeout: float | None = 1.0,
    blackboard: Blackboard | None = None,
    name: str | None = None,
    image_rotation: int = 0,
    device: str | None = None,
    **options: Any,
) -> Connection:
    """Connect to an e-puck2 over Wi-Fi (selector 15, Wi-Fi firmwares) at ``host:port``.

    ``timeout`` bounds each reply (images get three times as long); ``retries`` is how
    often an exchange is repeated after a timeout or garbage before
    :class:`~puckboard.errors.ConnectionLostError`. ``seed`` is accepted for the common
    factory signature and unused: a real robot is not seeded.
    """
    _reject_unknown("epuck2-wifi", options)
    if device:
        raise ValueError(
            f"--device {device} is for --backend sercom; the epuck2-wifi backend takes "
            "--host (and --port)"
        )
    if not host:
        raise ValueError(
            "the epuck2-wifi backend needs the robot's address: pass host='192.168.x.y' "
            "(on the command line: --host 192.168.x.y)"
        )
    port = DEFAULT_PORT if port is None else int(port)
    try:
        transport = TcpTransport(host, port, connect_timeout=connect_timeout)
    except ConnectionLostError as exc:
        if host in _THIS_MACHINE and port == DEFAULT_PORT:
            # nobody runs a real e-puck on this machine: this is the emulator, which cannot
            # take the robot's port 1000 without administrator rights
            raise ConnectionLostError(
                f"{exc}. On this machine it is probably 'puckboard emulate', which listens "
                f"on port {EMULATOR_WIFI_PORT} by default: add --port {EMULATOR_WIFI_PORT} "
                f"(in Python: port={EMULATOR_WIFI_PORT})"
            ) from exc.__cause__
        raise
    link = WifiLink(transport, timeout=timeout, retries=retries)
    return _connect(scene, link, EPUCK2, blackboard, name, command_timeout, image_rotation)


def open_sercom(
    scene: Scene | str | Path | None = None,
    *,
    seed: int = 0,
    device: str | None = None,
    model: str | None = None,
    baudrate: int = 115200,
    timeout: float = 1.0,
    retries: int = 2,
    command_timeout: float | None = 1.0,
    blackboard: Blackboard | None = None,
    name: str | None = None,
    image_rotation: int = 0,
    host: str | None = None,
    port: int | None = None,
    **options: Any,
) -> Connection:
    """Connect to an e-puck over advanced sercom on ``device``.

    ``device`` is ``/dev/rfcomm0`` (Linux Bluetooth), ``/dev/ttyACM0`` or
    ``/dev/cu.usbmodem…`` (e-puck2 USB), ``COM5`` (Windows), a pseudo-terminal, or a
    pyserial URL such as ``socket://127.0.0.1:10001``. ``model`` is ``"e-puck2"``
    (all-sensors/all-actuators commands) or ``"e-puck1"`` (individual commands); by
    default it follows the scene robot's profile. ``image_rotation`` (quarter turns
    counter-clockwise) fixes camera images that come out sideways.
    """
    _reject_unknown("sercom", options)
    if host or port:
        raise ValueError(
            "--host/--port are for --backend epuck2-wifi; the sercom backend takes --device "
            "(for a sercom emulator on TCP: --device socket://HOST:PORT)"
        )
    if not device:
        raise ValueError(
            "the sercom backend needs the serial device: pass device='/dev/rfcomm0' or 'COM5' "
            "(on the command line: --device PATH)"
        )
    spec_profile = _first_profile(scene)
    if model is None:
        model = "e-puck1" if spec_profile.name == EPUCK1.name else "e-puck2"
    profile = EPUCK1 if model == "e-puck1" else EPUCK2
    transport = SerialTransport(device, baudrate=baudrate)
    try:
        link = SercomLink(transport, model=model, timeout=timeout, retries=retries)
    except Exception:
        transport.close()
        raise
    return _connect(scene, link, profile, blackboard, name, command_timeout, image_rotation)


def _connect(
    scene: Scene | str | Path | None,
    link: Link,
    profile: RobotProfile,
    blackboard: Blackboard | None,
    name: str | None,
    command_timeout: float | None,
    image_rotation: int = 0,
) -> Connection:
    scene = _as_scene(scene)
    robots = tuple(getattr(scene, "robots", ()) or ())
    spec = robots[0] if robots else None
    if len(robots) > 1:
        log.warning(
            "scene %r has %d robots; the real robot plays the first one, %r",
            getattr(scene, "name", "?"), len(robots), spec.name if spec else "?",
        )  # fmt: skip
    robot_name = name or (spec.name if spec is not None else "epuck")
    start = (spec.x, spec.y, spec.theta) if spec is not None else (0.0, 0.0, 0.0)
    board = blackboard if blackboard is not None else Blackboard()
    try:
        adapter = EPuckReal(
            link,
            robot_name,
            profile=profile,
            blackboard=board,
            command_timeout=command_timeout,
            start_pose=start,
            image_rotation=image_rotation,
        )
        adapter.sense_all()  # fail now, with a clear message, rather than in the first cycle
    except Exception:
        link.close()
        raise
    return Connection(adapters={robot_name: adapter}, blackboard=board, stepper=None, world=None)


def _as_scene(scene: Scene | str | Path | None) -> Scene | None:
    """A Scene passes through; a shipped name or file path is loaded."""
    if isinstance(scene, (str, Path)):
        from ...scenario.scenefile import load_scene

        return load_scene(str(scene))
    return scene


def _first_profile(scene: Scene | str | Path | None) -> RobotProfile:
    scene = _as_scene(scene)
    robots = tuple(getattr(scene, "robots", ()) or ())
    if robots and getattr(robots[0], "profile", None):
        try:
            return get_profile(robots[0].profile)
        except ValueError:
            pass
    return EPUCK2


def _reject_unknown(backend: str, options: dict[str, Any]) -> None:
    if options:
        raise TypeError(
            f"the {backend} backend does not know the option(s) "
            f"{', '.join(sorted(options))}; see help(puckboard.backends.epuck.open_"
            f"{'wifi' if backend == 'epuck2-wifi' else 'sercom'})"
        )
