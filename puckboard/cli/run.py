"""``puckboard run``: one judged episode from the command line.

``puckboard run`` with no arguments runs the thesis's two-robot pass with the improved
controller in the embedded simulator. ``--json`` prints exactly one JSON object on
stdout (the fields of :meth:`puckboard.scenario.result.EpisodeResult.to_dict`) and nothing else,
so scripts can pipe it. The exit status is 0 whenever the run completed, whatever its
outcome; bad input (unknown scenario, unreadable scene, bad controller, bad ``--set``)
exits with 2 and one line on stderr. A controller that fails during the run ends it with
status 1: what puckboard refused (a ``command()`` that returns no finite
:class:`~puckboard.records.WheelCommand`, a key the robot does not have) is one line
naming robot, time and layer; an exception in the controller's own code prints the
traceback of that code's frames (not puckboard's or py_trees'), then that line.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING, Any

from .checks import (
    check_host,
    check_port,
    check_seconds,
    check_speed,
    check_writable,
    require,
    seed_type,
)
from .errors import (
    CliError,
    connection_loss_in_one_line,
    controller_error,
    first_line,
    missing_extra,
)
from .parsing import OneController, add_variation_argument, settings_help
from .web_view import add_web_arguments, serve_until_interrupted, start_web_view, web_url

if TYPE_CHECKING:
    from ..control.episode import Episode
    from ..scenario.result import EpisodeResult

#: A run longer than this (wall seconds) gets a progress indicator on stderr.
PROGRESS_AFTER_S = 0.5


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "run",
        help="run a scenario (default: the two-robot pass) and judge it",
        description=(
            "Run one episode of a scenario and print how it went: per-robot progress, "
            "passes, collisions, the outcome and what happened when. With --json, print "
            "one JSON object instead. Exit status 0 whenever the run completed."
        ),
    )
    parser.add_argument(
        "scenario",
        nargs="?",
        default="two-robot-pass",
        metavar="SCENARIO | SCENE_FILE",
        help="a shipped scene (see 'puckboard scenes') or a .toml/.json scene file "
        "(default: two-robot-pass)",
    )
    parser.add_argument(
        "--controller",
        action=OneController,
        default=None,
        metavar="stock|improved|robust|MODULE:FACTORY",
        help="controller for every robot (default: each robot's controller in the scene, "
        "improved in the shipped scenes)",
    )
    parser.add_argument("--seed", type=seed_type, default=0, help="random seed (default: 0)")
    parser.add_argument(
        "--profile",
        metavar="NAME|FILE.toml",
        help="robot profile for every robot: epuck, epuck-vrep, e-puck1 or a profile file "
        "(default: the scene's; see puckboard profiles)",
    )
    add_variation_argument(parser)
    parser.add_argument(
        "--duration", type=float, default=None, metavar="SECONDS",
        help="simulated seconds (default: the scene's)",
    )  # fmt: skip
    parser.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    parser.add_argument(
        "--full", action="store_true",
        help="run the whole duration even after the outcome is decided",
    )  # fmt: skip
    parser.add_argument(
        "--backend", default=None,
        help="embedded, coppeliasim, epuck2-wifi, sercom or fake "
        "(default: $PUCKBOARD_BACKEND, else embedded)",
    )  # fmt: skip
    parser.add_argument("--host", default=None, help="backend host (coppeliasim, epuck2-wifi)")
    parser.add_argument("--port", type=int, default=None, help="backend port")
    parser.add_argument("--device", default=None, help="serial device (sercom backend)")
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help=f"override a parameter: {settings_help()}; layer.<LayerName>.<attribute>; "
        "profile.<path> (every robot's, e.g. "
        "profile.prox_max_distance=0.045 or profile.prox_radius.side=31mm; paths: "
        "puckboard profiles show) or robot.<name>.profile.<path> (repeatable)",
    )
    parser.add_argument("--view", action="store_true", help="show a live view of the run")
    parser.add_argument(
        "--record", default=None, metavar="PATH",
        help="save the run: .npz (data), .gif or .mp4 (animation)",
    )  # fmt: skip
    parser.add_argument(
        "--plots", default=None, metavar="DIR", help="write plots of the run to DIR"
    )
    parser.add_argument(
        "--monitor", action="store_true", help="live table of every robot's blackboard"
    )
    add_web_arguments(parser)
    parser.add_argument(
        "--speed", type=float, default=None, metavar="X",
        help="with --web: run at X times real time so people can watch (default 1; 0 = as "
        "fast as it goes); the outcome is the same at any speed",
    )  # fmt: skip
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..control.episode import Episode
    from ..errors import LayerError, PuckboardError
    from ..scenario.overrides import parse_overrides

    try:
        overrides = parse_overrides(args.overrides)
    except ValueError as exc:
        raise CliError(str(exc)) from None
    if "variation" in overrides and getattr(args, "variation_given", False):
        raise CliError(
            f"--variation {args.variation} and --set variation={overrides['variation']}: the "
            "variation is given twice; give it once"
        )
    if args.profile is not None:
        overrides["robot.profile"] = args.profile
    if args.json and args.monitor:
        raise CliError("--monitor draws on stdout; it cannot be combined with --json")
    check_seconds(args.duration)
    check_port(args.port)  # a client port: refused now, not after its connection timeout
    check_host(args.host)
    check_port(args.web_port, "--web-port", listen_on=args.web_host if args.web else None)
    if args.speed is not None and not args.web:
        raise CliError("--speed paces the run for the web view; use it with --web")
    check_speed(args.speed)
    if args.monitor:
        require("rich", "--monitor")
    backend_options = {
        key: value
        for key, value in (("host", args.host), ("port", args.port), ("device", args.device))
        if value is not None
    }
    try:
        from ..backends.registry import abilities_of, backend_names, default_backend

        args.backend = args.backend or default_backend()
        remote = abilities_of(args.backend).remote
    except ValueError as exc:
        raise CliError(str(exc)) from None
    except ImportError:
        remote = True  # opening the backend names the extra to install
    if not remote and backend_options:
        names = [f"--{k}" for k in backend_options]
        flags = " and ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)
        verb, them = ("does", "it") if len(names) == 1 else ("do", "them")
        reaching = backend_names(lambda able: able.remote)
        raise CliError(
            f"{flags} {verb} not apply to the {args.backend} backend; use {them} with "
            f"--backend {', '.join(reaching[:-1])} or {reaching[-1]}"
        )
    if args.record is not None:
        check_writable(args.record, "--record")  # not found out after a long run
    if args.plots is not None:
        check_writable(args.plots, "--plots", folder=True)
    try:
        from ..scenario.scenefile import load_scene

        scene = load_scene(args.scenario)
    except PuckboardError as exc:
        raise CliError(str(exc)) from None
    try:
        episode = Episode(
            scene,
            controller=args.controller,
            seed=args.seed,
            backend=args.backend,
            overrides=overrides,
            variation=args.variation,
            **backend_options,
        )
    except Exception as exc:
        raise _build_error(exc, args.controller) from None
    duration = args.duration if args.duration is not None else episode.scene.duration
    try:
        episode.check_duration(duration)  # before any window opens or file is promised
    except ValueError as exc:
        episode.connection.close()
        raise CliError(first_line(exc)) from None
    outputs = None
    visuals = [
        flag
        for flag, wanted in (
            ("--view", args.view),
            ("--record", args.record),
            ("--plots", args.plots),
            ("--monitor", args.monitor),
        )
        if wanted
    ]
    if visuals:
        try:
            from ..viz.hooks import attach

            outputs = attach(
                episode, view=args.view, record=args.record, plots=args.plots, monitor=args.monitor
            )
        except ImportError as exc:
            episode.connection.close()
            raise missing_extra(exc, "/".join(visuals)) from None
        except ValueError as exc:
            episode.connection.close()
            raise CliError(first_line(exc)) from None
    web = None
    if args.web:
        from ..web import watch_episode

        speed = 1.0 if args.speed is None else (args.speed or None)
        try:
            web = start_web_view(
                lambda: watch_episode(episode, host=args.web_host, port=args.web_port, speed=speed),
                args,
            )
        except BaseException:
            episode.connection.close()
            raise
        print(f"live view: {web_url(web, args.web_host)}", file=sys.stderr, flush=True)
    progress = None if args.json and not sys.stderr.isatty() else _Progress(duration)
    if progress is not None and not args.monitor:
        episode.add_observer(progress.update)
    try:
        with connection_loss_in_one_line(episode):
            result = episode.run(duration, stop_early=not args.full)
    except Exception as exc:
        failure = episode.loop.failure
        if failure is None:
            raise
        if isinstance(exc, PuckboardError):
            # puckboard refused what a layer did (a command that is no WheelCommand, a
            # speed that is not finite, an unknown key): the line says what and where
            problem = exc.problem if isinstance(exc, LayerError) else str(exc)
            print(f"puckboard run: error: {failure.describe()}: {problem}", file=sys.stderr)
            return 1
        # the controller's own code raised: its own frames say what, the last line where
        from ..usercode import own_traceback

        sys.stderr.write(own_traceback(exc))
        print(
            f"puckboard run: error: {failure.describe()}: {type(exc).__name__}: {exc}",
            file=sys.stderr,
        )
        return 1
    finally:
        if progress is not None:
            progress.close()
    if args.json:
        sys.stdout.write(json.dumps(result.to_dict()) + "\n")
        sys.stdout.flush()
    else:
        print(format_summary(result, simulated=episode.loop.synchronous))
    for path in getattr(outputs, "written", None) or ():
        print(f"wrote {path}", file=sys.stderr)
    if web is not None:
        _keep_web_view(web)
    return 0


def _keep_web_view(web: Any) -> None:
    """Keep the page (and its verdict) up after the run until Ctrl-C."""
    print(
        f"the live view stays at {web.url} with the verdict; Ctrl-C ends it",
        file=sys.stderr, flush=True,
    )  # fmt: skip
    serve_until_interrupted(web)


def _build_error(exc: Exception, controller: str | None) -> BaseException:
    """What to raise when building the episode failed: the controller's problem as every
    command says it (:func:`~puckboard.cli.errors.controller_error`), one line for other
    bad input (a backend's), else the error itself (a bug: its traceback)."""
    shown = controller_error(exc, controller)
    if shown is not None:
        return shown
    if isinstance(exc, OSError):
        return CliError(first_line(exc))
    return exc


def realtime_text(factor: float | None) -> str:
    """``185x``, ``1.9x``, ``0.12x``: whole numbers from 10 up, two significant figures
    below, so a run slower than real time does not read "0x"."""
    if not factor:
        return "0x"
    return f"{factor:.0f}x" if factor >= 10 else f"{float(f'{factor:.2g}'):g}x"


def _loop_timing(d: dict[str, Any]) -> str:
    """``; control every 100 ms, 50 ms latency`` when the loop is not one tick per step."""
    if "control_period_s" not in d:
        return ""
    cycle = d.get("control_cycle")
    if cycle is None:
        latency = f"{d['control_latency_s'] * 1000:g} ms latency"
    else:
        latency = (
            f"latency per cycle median {cycle['latency_median_s'] * 1000:.3g} ms, 90 % "
            f"{cycle['latency_p90_s'] * 1000:.3g} ms, max {cycle['latency_max_s'] * 1000:.3g} ms"
            if "latency_median_s" in cycle
            else f"{d['control_latency_s'] * 1000:g} ms latency"
        )
        latency += f", {cycle['repeated']:.0%} of readings repeated"
    return f"; control every {d['control_period_s'] * 1000:g} ms, {latency}"


def _condition_lines(conditions: dict[str, Any] | None) -> list[str]:
    """What ``--variation reality-gap`` drew, one setting a line (none for other
    variations); per obstacle and per robot values by name."""
    if not conditions:
        return []
    lines = ["", "conditions drawn (reality-gap):"]
    for name, value in conditions.items():
        if isinstance(value, dict):
            shown = ", ".join(f"{k} {v:.4g}" for k, v in value.items())
        else:
            shown = value if isinstance(value, str) else f"{value:.4g}"
        lines.append(f"  {name} = {shown}")
    return lines


def format_summary(result: EpisodeResult, *, simulated: bool = True) -> str:
    """A readable summary of an :class:`~puckboard.scenario.result.EpisodeResult`;
    ``simulated=False`` for a run on a robot (real or emulated), whose time is the run's
    own, not simulated."""
    d = result.to_dict()
    steps = (
        f"{d['steps']} step{'s' * (d['steps'] != 1)} of {d['dt_s'] * 1000:g} ms{_loop_timing(d)}"
    )
    if simulated:
        clock = (
            f"{d['sim_time_s']:.1f} s simulated in {d['wall_s']:.2f} s "
            f"({realtime_text(d['realtime_factor'])} real time, {steps})"
        )
    else:
        clock = f"{d['sim_time_s']:.1f} s on the robot ({steps})"
    lines = [
        f"{d['scenario']}  controller={d['controller']}  seed={d['seed']}  {clock}",
        "",
        f"{'robot':<12}{'profile':<12}{'laps':>7}{'driven m':>10}{'collisions':>12}"
        f"{'on line':>9}{'obstacles':>11}{'passed other':>14}",
    ]
    alone = len(d["robots"]) < 2  # no other robot to pass: neither yes nor no
    for r in d["robots"]:
        passed = "-" if alone else "yes" if r["passed_other"] else "no"
        lines.append(
            f"{r['name']:<12}{r['profile']:<12}{_unsigned_zero(r['progress_laps']):>7.2f}"
            f"{r['distance_m']:>10.2f}"
            f"{r['collisions']:>12d}{r['on_line_fraction'] * 100:>8.0f}%"
            f"{r['obstacles_passed']:>11d}{passed:>14}"
        )
    lines += _profile_value_lines(d["robots"])
    lines += _condition_lines(d.get("conditions"))
    lines.append("")
    if d["success"]:
        lines.append("outcome: SUCCESS")
    else:
        from ..scenario.judge import FAILURES

        lines.append(f"outcome: FAILED ({d['failure']}: {FAILURES.get(d['failure'], '')})")
        if len(d["failures"]) > 1:
            lines.append(f"failures detected, in order: {', '.join(d['failures'])}")
    if d["events"]:
        from ..viz.style import event_label

        lines.append("")
        lines.append("events:")
        for e in d["events"]:  # the robot set off by a colon: 'left: left the line'
            who = f"{e['robot']}: " if e["robot"] else ""
            lines.append(f"  {e['time_s']:7.2f} s  {who}{event_label(e['kind'])}")
    return "\n".join(lines)


def _unsigned_zero(value: float, digits: int = 2) -> float:
    """``value``, or 0.0 when it rounds to zero at ``digits``: a robot that slid back a
    millimetre made no progress, and the table should not say ``-0.00``."""
    return value if round(value, digits) != 0 else 0.0


def _profile_value_lines(robots: list[dict[str, Any]]) -> list[str]:
    """The robots' uncertain numbers that differ from their shipped profile's, one row each
    (nothing when every robot is as shipped): what makes this run's robots this run's."""
    from ..profile import get_profile, profile_values

    shipped: list[dict[str, float]] = []
    for r in robots:
        try:
            shipped.append(profile_values(get_profile(r["profile"])))
        except ValueError:  # a profile file's own name: every value is worth showing
            shipped.append({})
    paths: list[str] = []
    for r, ref in zip(robots, shipped):
        for path, value in r.get("profile_values", {}).items():
            if ref.get(path) != value and path not in paths:
                paths.append(path)
    if not paths:
        return []
    width = max(len(p) for p in paths) + 2
    lines = [
        "",
        "profile values unlike the shipped profile's (SI; exact in --json; "
        "--set profile.PATH=VALUE repeats one):",
        f"  {'':<{width}}" + "".join(f"{r['name']:>14}" for r in robots),
    ]
    for path in paths:
        cells = "".join(
            f"{r.get('profile_values', {}).get(path, float('nan')):>14.6g}" for r in robots
        )
        lines.append(f"  {path:<{width}}{cells}")
    return lines


class _Progress:
    """A progress indicator on stderr, shown only once a run has taken a moment:
    rich's bar when rich is installed and stderr is a terminal, else a plain line."""

    def __init__(self, duration: float) -> None:
        import time

        self.duration = max(duration, 1e-9)
        self.clock = time.perf_counter
        self.t0 = self.clock()
        self.bar: Any = None
        self.task: Any = None
        self.plain = False
        self.last_plain = 0.0

    def _start(self) -> None:
        if sys.stderr.isatty():
            try:
                from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

                self.bar = Progress(
                    TextColumn("simulating"),
                    BarColumn(),
                    TextColumn("{task.completed:.0f}/{task.total:.0f} s"),
                    TimeRemainingColumn(),
                    transient=True,
                )
                self.bar.start()
                self.task = self.bar.add_task("run", total=self.duration)
                return
            except ImportError:
                pass
        self.plain = True

    def update(self, episode: Episode) -> None:
        now = self.clock()
        if self.bar is None and not self.plain:
            if now - self.t0 < PROGRESS_AFTER_S:
                return
            self._start()
        t = episode.time
        if self.bar is not None:
            self.bar.update(self.task, completed=min(t, self.duration))
        elif now - self.last_plain >= 1.0:
            self.last_plain = now
            end = "\r" if sys.stderr.isatty() else "\n"
            print(
                f"simulating: {t:.0f}/{self.duration:.0f} s", end=end, file=sys.stderr, flush=True
            )

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
        elif self.plain and sys.stderr.isatty():
            print(" " * 40, end="\r", file=sys.stderr, flush=True)
