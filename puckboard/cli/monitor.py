"""``puckboard monitor``: a live table of every robot's blackboard keys, any backend."""

from __future__ import annotations

import argparse

from .checks import check_seconds, check_speed, require, seed_type
from .errors import CliError, connection_loss_in_one_line, controller_error
from .parsing import OneController


def register(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser(
        "monitor",
        help="live table of the robots' sensor values, their age and update rate",
        description=(
            "Run a scenario (or drive a real robot) with a live terminal table of every "
            "blackboard key: value, age and update rate. Works with every backend; a "
            "simulation runs at real time (--speed) so the values can be read as they change."
        ),
    )
    p.add_argument(
        "scenario", nargs="?", default="two-robot-pass", help="scene name or .toml/.json file"
    )
    p.add_argument(
        "--backend",
        default=None,
        help="the backend to watch, as puckboard run takes it (default: $PUCKBOARD_BACKEND, "
        "else embedded)",
    )
    p.add_argument(
        "--controller",
        action=OneController,
        default=None,
        metavar="SPEC",
        help="override every robot's controller",
    )
    p.add_argument(
        "--still",
        action="store_true",
        help="keep the wheels still and only watch the sensors (a real robot on the desk)",
    )
    p.add_argument("--seed", type=seed_type, default=0, help="seed of the simulation's noise")
    p.add_argument(
        "--duration",
        type=float,
        default=None,
        metavar="S",
        help="seconds to run (default: the scene's)",
    )
    p.add_argument("--host", default=None, help="backend host (CoppeliaSim, e-puck2 Wi-Fi)")
    p.add_argument("--port", type=int, default=None, help="backend port")
    p.add_argument(
        "--device", default=None, help="serial device (sercom), e.g. /dev/rfcomm0 or COM5"
    )
    p.add_argument(
        "--refresh", type=float, default=4.0, help="table redraws per second (default 4)"
    )
    p.add_argument(
        "--speed",
        type=float,
        default=1.0,
        metavar="X",
        help="simulated runs go at X times real time so the table can be read (default 1; "
        "0 = as fast as the machine can)",
    )
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..control.episode import Episode
    from ..errors import PuckboardError
    from ..viz.monitor import SensorMonitor

    if args.refresh <= 0:
        raise CliError("--refresh must be positive")
    check_speed(args.speed)
    if args.still and args.controller:
        raise CliError("--still and --controller exclude each other")
    check_seconds(args.duration)
    require("rich", "the live sensor table")  # before a backend, perhaps a robot, is opened
    controller = _still if args.still else args.controller
    options = {
        k: getattr(args, k) for k in ("host", "port", "device") if getattr(args, k) is not None
    }
    try:
        episode = Episode(
            args.scenario,
            controller=controller,
            seed=args.seed,
            backend=args.backend,
            **options,
        )
    except Exception as exc:
        shown = controller_error(exc, args.controller)
        if shown is not None:
            raise shown from None
        if isinstance(exc, (KeyError, PuckboardError)):
            raise CliError(str(exc)) from exc  # a backend's missing extra is named by the registry
        raise
    try:
        episode.check_duration(args.duration)
    except ValueError as exc:
        episode.connection.close()
        raise CliError(str(exc)) from None
    SensorMonitor.for_episode(episode, refresh=args.refresh).attach(episode)
    if args.speed > 0:
        from ..control.pacing import RealTimePacer

        episode.add_observer(RealTimePacer(args.speed))
    with connection_loss_in_one_line(episode):
        result = episode.run(args.duration)
    verdict = "success" if result.success else f"failure ({result.failure})"
    print(f"{result.scenario}: {verdict} after {result.sim_time_s:.1f} s")
    return 0


def _still():  # type: ignore[no-untyped-def]
    """A controller with one layer that always applies and commands zero speed."""
    from ..behaviours import Controller, Layer
    from ..records import WheelCommand

    class Still(Layer):
        def command(self, frame):  # type: ignore[no-untyped-def]
            return WheelCommand.stop()

    return Controller([Still()], name="still")
