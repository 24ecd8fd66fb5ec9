"""``puckboard serve``: serve a scene over CoppeliaSim's ZeroMQ remote API.

The embedded simulator holds the scene; clients drive it exactly as they would drive
CoppeliaSim: the official Python client, EPuckVRep, ``puckboard run --backend
coppeliasim``. Each robot of the scene is served as a copy of the stock e-puck model
(ePuck, ePuck#0, ePuck#1 ...), keeps its start pose from the scene, and moves only when
a client commands it. The simulation starts when a client calls sim.startSimulation;
while clients are in stepping mode it advances when every one of them has called
sim.step, otherwise in real time. sim.stopSimulation restores the scene. As in
CoppeliaSim, a silent stepping client holds the others until its idle timeout; for a
class, --stepping-timeout frees them sooner.

Serving a classroom: bind all interfaces explicitly with --host 0.0.0.0 and give the
students this machine's address. Nothing a client sends is executed: only the listed
sim.* functions are served.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from .bind import bind_error_message
from .checks import check_port, check_seconds, seed_type
from .errors import CliError, missing_extra
from .parsing import add_variation_argument, help_text
from .web_view import add_web_arguments, start_web_view, web_url


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "serve",
        help="serve a scene over CoppeliaSim's ZeroMQ remote API (for EPuckVRep and classes)",
        description=help_text(__doc__),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=(
            "examples:\n"
            "  puckboard serve two-robot-pass\n"
            "  puckboard run two-robot-pass --backend coppeliasim --port 23000\n"
            "  puckboard serve my-scene.toml --host 0.0.0.0 --stepping-timeout 10   "
            "# a whole class\n"
            "  puckboard serve arena --web                   # and watch it at http://127.0.0.1:8080/\n"
        ),
    )
    p.add_argument(
        "scenario",
        nargs="?",
        default="two-robot-pass",
        help="scene name or scene file (default: two-robot-pass)",
    )
    p.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default 127.0.0.1, this machine only; 0.0.0.0 = every "
        "interface, for a class)",
    )
    p.add_argument(
        "--port", type=int, default=23000, help="TCP port (default 23000, CoppeliaSim's; 0 = any)"
    )
    p.add_argument("--seed", type=seed_type, default=0, help="seed of the simulation's noise")
    p.add_argument(
        "--profile",
        default="epuck-vrep",
        metavar="NAME|FILE.toml",
        help="robot profile of every served robot, shipped or a profile file (default "
        "epuck-vrep: the server stands in for CoppeliaSim and its stock e-puck model; "
        "'scene' keeps the scene's)",
    )
    add_variation_argument(p)
    p.add_argument(
        "--stepping-timeout",
        type=float,
        default=None,
        metavar="S",
        help="a stepping client silent this long stops holding the others back (default: "
        "none, as CoppeliaSim: it holds them until its idle timeout; 10 suits a class)",
    )
    p.add_argument(
        "--idle-timeout",
        type=float,
        default=600.0,
        metavar="S",
        help="forget a client silent this long and stop its robots (default 600 s, the "
        "Python client's own; a client asking for less gets less)",
    )
    p.add_argument(
        "--stock-script",
        action="store_true",
        help="serve the e-puck's script without puckboard's sense-all and set-wheels "
        "functions, as a plain CoppeliaSim model (clients read sensor by sensor)",
    )
    add_web_arguments(p)
    p.add_argument(
        "--functions",
        action="store_true",
        help="list the served sim.* functions and exit",
    )
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    import logging

    from ..profile import get_profile

    if args.functions:
        return _list_functions()
    check_port(args.port, listen_on=args.host)
    check_port(args.web_port, "--web-port", listen_on=args.web_host if args.web else None)
    check_seconds(args.stepping_timeout, "--stepping-timeout")
    check_seconds(args.idle_timeout, "--idle-timeout")
    try:
        from ..backends.coppeliasim.server.socket_loop import RemoteApiServer
    except ImportError as exc:
        raise missing_extra(exc, "serving over the ZeroMQ remote API") from None
    scene = served_scene(args)
    try:
        server = RemoteApiServer(
            scene,
            host=args.host,
            port=args.port,
            seed=args.seed,
            stepping_timeout=args.stepping_timeout,
            max_idle=args.idle_timeout,
            profile=None,  # the scene's robots have theirs already
            script_functions=not args.stock_script,
        )
    except ImportError as exc:
        raise missing_extra(exc, "serving over the ZeroMQ remote API") from None
    except OSError as exc:
        raise CliError(bind_error_message(exc, args.host, args.port)) from None
    web = None
    if args.web:
        try:
            from ..web import watch_server

            web = start_web_view(lambda: watch_server(server, host=args.web_host,
                                                      port=args.web_port), args)  # fmt: skip
        except BaseException:
            server.close()
            raise
    shown_host = "127.0.0.1" if args.host in ("127.0.0.1", "localhost") else args.host
    out = sys.stdout
    print(
        f"serving scene {scene.name!r} (dt {scene.dt:g} s, seed {args.seed}) over the ZeroMQ "
        f"remote API, protocol 2, at tcp://{args.host}:{server.port}",
        file=out,
    )
    profiles = sorted({get_profile(r.profile).name for r in server.api.world.scene.robots})
    varied = f"; robots drawn by --variation {args.variation}" if args.variation != "none" else ""
    print(f"  robot profile: {', '.join(profiles)} (--profile to change){varied}", file=out)
    for line in server.describe():
        print(f"  {line}", file=out)
    if args.host in ("0.0.0.0", "*"):
        print("  listening on every interface: clients use this machine's address", file=out)
        shown_host = "<this machine's address>"
    print("connect with:", file=out)
    print(
        f"  puckboard run {args.scenario} --backend coppeliasim --host {shown_host} "
        f"--port {server.port}",
        file=out,
    )
    print(
        f"  python: RemoteAPIClient('{shown_host}', {server.port}).require('sim'), or "
        f"EPuckVRep(object_path='ePuck', host='{shown_host}', port={server.port})",
        file=out,
    )
    if web is not None:
        print(f"live view for the class: {web_url(web, args.web_host)}", file=out)
    print(
        "Ctrl-C stops the server; clients coming and going are logged below", file=out, flush=True
    )
    remote_log = logging.getLogger("puckboard.backends.coppeliasim.server")
    if remote_log.getEffectiveLevel() > logging.INFO:
        remote_log.setLevel(logging.INFO)  # a lecturer wants to see who connects
    try:
        server.serve_forever()  # until Ctrl-C, which main() ends with status 130
    finally:
        server.close()
        if web is not None:
            web.close()
        print(
            f"server stopped after {server.requests} requests "
            f"({server.errors} answered with an error), t={server.api.world.time:.2f} s",
            file=out,
        )
    return 0


def served_scene(args: argparse.Namespace) -> Any:
    """The scene to serve: its robots given ``--profile`` (unless 'scene') and, with
    ``--variation plausible``, each drawn within its plausible ranges."""
    from ..errors import SceneError
    from ..scenario.conversion import for_seed
    from ..scenario.robot_profiles import scene_profile
    from ..scenario.scenefile import load_scene
    from ..scenario.variation import vary_scene

    try:
        scene = for_seed(load_scene(args.scenario), args.seed)  # a generated scene's track
        if args.profile != "scene":
            scene = scene.with_profile(scene_profile(args.profile))
        return vary_scene(scene, args.seed, args.variation)
    except (SceneError, FileNotFoundError, KeyError, ValueError) as exc:
        raise CliError(str(exc)) from None


def _list_functions() -> int:
    """Print the served functions, one per line (the docs' table has their semantics)."""
    try:
        from ..backends.coppeliasim.server.simapi import SimApi
    except ImportError as exc:
        raise missing_extra(exc, "serving over the ZeroMQ remote API") from None
    from ..scenario.scenefile import load_scene

    names = sorted(SimApi(load_scene("two-robot-pass")).functions)
    for name in names:
        print(name)
    print(
        f"{len(names)} functions; their CoppeliaSim semantics and differences: "
        "docs/coppeliasim.md, 'Every served function'",
        file=sys.stderr,
    )
    return 0
