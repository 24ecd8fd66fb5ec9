"""``puckboard emulate``: a simulated e-puck that speaks the real robot's protocol.

Serves the first robot of a scene over the e-puck2 Wi-Fi protocol (TCP) or advanced
sercom (a pseudo-terminal on Linux/macOS, or TCP with ``--port``), paced in real time
(or ``--speed`` times faster),
and prints the judge's verdict (the ``puckboard run --json`` fields) when it stops:
when the client is done (it disconnects, or is silent for ``--idle-timeout`` s), after
``--duration`` seconds counted from its first command, or on Ctrl-C (then the verdict
says so, and the exit status is 130).
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from .bind import bind_error_message
from .checks import check_port, check_seconds, seed_type
from .errors import CliError
from .parsing import help_text

#: The robot uses 1000, which needs administrator rights to bind; kept equal to
#: backends.epuck.factories.EMULATOR_WIFI_PORT (tested), not imported, so --help stays fast.
DEFAULT_WIFI_PORT = 10000


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "emulate",
        help="emulate a real e-puck's protocol (Wi-Fi or sercom) with the simulator behind it",
        description=help_text(__doc__),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=(
            "example:\n"
            "  puckboard emulate line-follow --protocol wifi --port 10000\n"
            "  puckboard run line-follow --backend epuck2-wifi --host 127.0.0.1 --port 10000\n"
        ),
    )
    p.add_argument(
        "scenario",
        nargs="?",
        default="line-follow",
        help="scene name or file (default: line-follow)",
    )
    p.add_argument(
        "--protocol",
        choices=("wifi", "sercom"),
        default="wifi",
        help="wifi: the e-puck2's Wi-Fi protocol over TCP (default); sercom: advanced sercom, "
        "as over Bluetooth or USB serial",
    )
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    p.add_argument(
        "--port",
        type=int,
        default=None,
        help=f"TCP port (wifi: default {DEFAULT_WIFI_PORT}; sercom: serve over TCP instead of a "
        "pseudo-terminal, connect with --device socket://HOST:PORT; 0 = any free port)",
    )
    p.add_argument(
        "--duration",
        type=float,
        default=None,
        help="at most this many seconds of robot time (default: the scene's duration + 10 s)",
    )
    p.add_argument(
        "--idle-timeout",
        type=float,
        default=2.0,
        help="end when the client sends nothing for this long (s; 0: never); a TCP client "
        "that disconnects ends the run at once",
    )
    p.add_argument("--seed", type=seed_type, default=0, help="seed of the simulation's noise")
    p.add_argument(
        "--speed",
        type=float,
        default=1.0,
        metavar="X",
        help="run the robot X times faster than real time (default 1, as a real robot): "
        "for tests and demonstrations that need not wait; a client sees it move X times faster",
    )
    p.add_argument(
        "--profile",
        default="epuck",
        metavar="NAME|FILE.toml",
        help="robot profile of the emulated robot and the others, shipped or a profile file "
        "(default epuck: it stands in for the physical robot; 'scene' keeps the scene's)",
    )
    p.add_argument(
        "--others",
        choices=("controller", "still"),
        default="controller",
        help="the scene's other robots run their own controllers (default) or stand still",
    )
    p.add_argument(
        "--link",
        default=None,
        metavar="LINK",
        help="hold every reply back by a latency drawn within this link's range "
        "(bluetooth-sercom, epuck2-wifi, usb-sercom ...; puckboard profiles show links), so "
        "a client runs at that link's pace (default: answer at once)",
    )
    p.add_argument("--json", action="store_true", help="print only the verdict as JSON on stdout")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..backends.epuck.emulator import pty_available
    from ..control.emulation import Emulation
    from ..errors import SceneError

    check_seconds(args.duration)
    check_port(args.port, listen_on=args.host)
    if not (math.isfinite(args.speed) and args.speed > 0):
        raise CliError(f"--speed must be a finite number > 0 (times real time), got {args.speed}")
    if args.idle_timeout < 0:
        raise CliError(f"--idle-timeout must be >= 0 seconds, got {args.idle_timeout}")
    if args.link is not None:
        from ..profile.links import LINKS

        if args.link not in LINKS:
            raise CliError(f"--link {args.link!r}: unknown link; links: {', '.join(LINKS)}")
    serial = None
    port = args.port
    if args.protocol == "wifi":
        port = DEFAULT_WIFI_PORT if port is None else port
    elif port is not None:
        serial = "tcp"
    elif not pty_available():
        raise CliError(
            "serving sercom on a pseudo-terminal needs Linux or macOS; on this system add "
            "--port 10001 and connect with --device socket://127.0.0.1:10001, or use "
            "--protocol wifi"
        )
    else:
        serial = "pty"
    try:
        emulation = Emulation(
            args.scenario,
            protocol=args.protocol,
            host=args.host,
            port=port or 0,
            seed=args.seed,
            serial=serial,
            others=args.others,
            idle_timeout=args.idle_timeout or None,
            realtime=args.speed,
            profile=None if args.profile == "scene" else args.profile,
            link=args.link,
        )
    except (SceneError, FileNotFoundError, KeyError, ValueError) as exc:
        raise CliError(str(exc)) from None
    except OSError as exc:
        if serial == "pty":  # no socket involved: the system's reason says it all
            raise CliError(str(exc)) from None
        raise CliError(bind_error_message(exc, args.host, port or 0)) from None
    emulation.start()  # listening before the banner says where to connect
    info = emulation.info
    banner = sys.stderr if args.json else sys.stdout
    interrupted = False
    try:  # from the banner on, Ctrl-C ends the emulation with its verdict (or none)
        print(
            f"emulating robot {emulation.robot.name!r} of scene {emulation.scene.name!r} over "
            f"{'Wi-Fi (TCP)' if args.protocol == 'wifi' else 'advanced sercom'} at "
            f"{info.endpoint}",
            file=banner,
        )
        print(f"connect with: {info.command_line(args.scenario)}", file=banner)
        if emulation.link is not None:
            print(held_back_text(emulation.link.name, emulation.link.latency), file=banner)
        print(
            "the clock starts with the first command; the run ends when the client is done, "
            "or on Ctrl-C",
            file=banner,
            flush=True,
        )
        result = emulation.run(args.duration)
    except KeyboardInterrupt:
        interrupted = True
        emulation.ended_by = "interrupted"
        emulation.close()
        result = emulation.result()
    data = result.to_dict()
    if args.json:
        print(json.dumps(data, indent=2))
    elif interrupted and not emulation.robot.commands:  # no verdict: nothing was run
        print(f"{data['scenario']}: no run (interrupted by Ctrl-C before any client connected)")
    else:
        verdict = "success" if data["success"] else f"failure: {data['failure']}"
        ended = emulation.ended_by or "no client"
        if interrupted:
            ended = "interrupted by Ctrl-C; a client was driving"
        print(
            f"{data['scenario']}: {verdict} after {data['sim_time_s']:.1f} s of robot time "
            f"(ended: {ended})"
        )
        for r in data["robots"]:
            print(
                f"  {r['name']}: {r['progress_laps']:.2f} laps, {r['distance_m']:.2f} m, "
                f"on line {100 * r['on_line_fraction']:.0f}%, {r['collisions']} collisions"
            )
    return 130 if interrupted else 0


def held_back_text(link: str, latency: tuple[float, float]) -> str:
    """How long the emulator holds each reply back on ``link`` (its latency range, s):
    a range, one number, or none at all (a synchronous simulator's loop)."""
    low, high = (round(v * 1000, 1) for v in latency)
    if high == 0:
        return f"no reply is held back: {link} has no latency"
    if low == high:
        return f"every reply is held back {low:g} ms, as on {link}"
    return f"every reply is held back {low:g}-{high:g} ms, as on {link}"
