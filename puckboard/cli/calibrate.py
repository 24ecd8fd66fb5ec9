"""``puckboard calibrate ir|link``: measure your robot's IR sensors, or its link's timing,
and write a profile file.

``calibrate link`` times ``--rounds`` control cycles over the robot's link (read every
sensor, command the wheels to zero: the robot does not move) and writes the period and
latency to run at into the ``[link]`` table of ``--out`` (created, or updated in place),
so ``--profile FILE.toml`` runs the simulator at your link's timing.

``calibrate ir``:
The robot starts touching a white wall, facing it. It backs away in small steps, by its
step counters, touching the wall again before each step, and at every stop turns in
place to look at the wall with each of its eight sensors in turn, reading each several
times. Each sensor's gain and offset are then fitted (least squares) against the
simulator's own response curve, and written to a profile file (base epuck) that
``--profile FILE.toml`` gives to run, sweep, serve and emulate, so the simulator predicts
your robot. ``--dry-run`` prints the plan and moves nothing.

Without a robot, try it on the emulated one, whose sensors a profile file can make
unlike the table: ``puckboard emulate calibration-wall --profile FILE.toml``.

The wheels are stopped at the end, on any error and on Ctrl-C (exit status 130); after
Ctrl-C the poses measured so far are fitted and written, when they are enough. A run
that cannot work (no wall seen, wheels that do not turn, a robot that does not move away,
a sensor that does not respond or reads full scale) stops with one line saying what to
fix (exit status 1); bad input is one line and exit status 2.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .checks import check_host, check_port, check_writable
from .errors import CliError, missing_extra
from .parsing import help_text

if TYPE_CHECKING:
    from collections.abc import Callable, Sequence

    from ..backends.base import Connection
    from ..calibration.fit import SensorFit
    from ..calibration.plan import CalibrationPlan
    from ..calibration.readings import Measurements, PoseReading, Progress
    from ..calibration.response import WallModel



def length(text: str) -> float:
    """argparse type of a distance: metres, or a number with mm, cm or m (read as every
    quantity is, :func:`puckboard.units.read_quantity`)."""
    from ..units import read_quantity

    try:
        return read_quantity("distance", text, "m")
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected a distance in metres or with a unit (60mm, 6cm, 0.06), got {text!r}"
        ) from None


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "calibrate",
        help="measure your e-puck's IR sensors against a wall and write a profile file",
        description=help_text(__doc__),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=(
            "examples:\n"
            "  puckboard calibrate ir --dry-run\n"
            "  puckboard calibrate ir --backend epuck2-wifi --host 192.168.1.42 "
            "--out my-epuck.toml\n"
            "  puckboard calibrate ir --backend sercom --device /dev/rfcomm0 --out my-epuck.toml\n"
            "  puckboard calibrate link --backend sercom --device /dev/rfcomm0 "
            "--out my-epuck.toml\n"
            "  puckboard run two-robot-pass --profile my-epuck.toml\n"
        ),
    )
    p.add_argument(
        "what",
        choices=("ir", "link"),
        help="what to calibrate: ir, the proximity sensors; link, the link's period and latency",
    )
    p.add_argument(
        "--rounds", type=int, default=200, metavar="N",
        help="link: control cycles to time (default 200, about 10-20 s on Bluetooth)",
    )  # fmt: skip
    p.add_argument(
        "--backend",
        default=None,
        help="the robot's link: epuck2-wifi (with --host) or sercom (with --device)",
    )
    p.add_argument("--host", default=None, help="the robot's address (epuck2-wifi)")
    p.add_argument("--port", type=int, default=None, help="TCP port (epuck2-wifi; default 1000)")
    p.add_argument("--device", default=None, help="serial device (sercom), e.g. /dev/rfcomm0")
    p.add_argument(
        "--profile",
        default="epuck",
        metavar="NAME|FILE.toml",
        help="what the robot is believed to be before calibrating: its wheels and axle count "
        "the moves, its body radius says where touching the wall is (default epuck; a "
        "profile file's other numbers are kept in the result)",
    )
    p.add_argument("--out", default=None, metavar="FILE.toml", help="the profile file to write")
    p.add_argument("--name", default=None, help="the robot's name in the file (default: its stem)")
    p.add_argument(
        "--distance", type=length, default=None, metavar="LENGTH",
        help="how far to back away from touching (default 60mm)",
    )  # fmt: skip
    p.add_argument(
        "--step", type=length, default=None, metavar="LENGTH",
        help="distance between stops (default 3mm)",
    )  # fmt: skip
    p.add_argument(
        "--samples", type=int, default=None, metavar="N", help="readings per pose (default 10)"
    )
    p.add_argument(
        "--sample-period", type=float, default=None, metavar="S",
        help="seconds between readings (default 0.05, the firmware's slow IR refresh)",
    )  # fmt: skip
    p.add_argument(
        "--dry-run", action="store_true", help="print the plan (moves, distances, duration); "
        "connect to nothing, move nothing"
    )  # fmt: skip
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress display")
    p.set_defaults(func=main)


def _plan(args: argparse.Namespace) -> CalibrationPlan:
    from ..calibration.plan import make_plan
    from ..errors import PuckboardError
    from ..profile import get_profile, resolve_profile

    try:
        profile = get_profile(resolve_profile(args.profile))
    except PuckboardError as exc:
        raise CliError(str(exc)) from None
    options = {
        key: value
        for key, value in (
            ("distance", args.distance),
            ("step", args.step),
            ("samples", args.samples),
            ("sample_period", args.sample_period),
        )
        if value is not None
    }
    try:
        return make_plan(profile, **options)
    except ValueError as exc:
        flag = next(
            (f for f in ("distance", "step", "samples", "sample period") if str(exc).startswith(f)),
            "",
        )
        prefix = f"--{flag.replace(' ', '-')}: " if flag else ""
        raise CliError(prefix + str(exc)) from None


def _out_path(args: argparse.Namespace) -> Path:
    if not args.out:
        raise CliError(
            "--out FILE.toml is needed: the profile file to write (or --dry-run to see the plan)"
        )
    out = Path(args.out)
    if out.suffix.lower() != ".toml":
        raise CliError(f"--out {args.out!r}: profile files are TOML and end in .toml")
    return check_writable(out, "--out")


def _check_name(name: str) -> None:
    """The robot's name in the file, checked before the robot moves: the file must load."""
    from ..profile import profile_names

    if not name.strip():
        raise CliError("--name: give your robot a name, e.g. --name my-epuck")
    if name in profile_names():
        raise CliError(
            f"the profile's name {name!r} is a shipped profile's; give your robot its own: "
            "--name my-epuck (or an --out file of another name)"
        )


def _backend_options(args: argparse.Namespace) -> dict[str, Any]:
    from ..backends.registry import abilities_of

    try:
        calibratable = bool(args.backend) and abilities_of(args.backend).calibratable
    except ValueError as exc:
        raise CliError(f"--backend {args.backend}: {exc}") from None
    except ImportError as exc:
        raise missing_extra(exc, f"--backend {args.backend}") from None
    if not calibratable:
        given = f"--backend {args.backend}" if args.backend else "no --backend"
        raise CliError(
            f"{given}: calibrate {args.what} drives a real e-puck, --backend epuck2-wifi "
            "--host IP or "
            "--backend sercom --device DEVICE (no robot? 'puckboard emulate calibration-wall' "
            "serves an emulated one)"
        )
    check_port(args.port)
    check_host(args.host)
    return {
        key: value
        for key, value in (("host", args.host), ("port", args.port), ("device", args.device))
        if value is not None
    }


def _open(backend: str, options: dict[str, Any]) -> Connection:
    from ..backends.registry import open_backend
    from ..errors import PuckboardError

    try:
        return open_backend(backend, None, **options)
    except ImportError as exc:
        raise missing_extra(exc, f"--backend {backend}") from None
    except (PuckboardError, ValueError, TypeError, OSError) as exc:
        text = str(exc).strip().splitlines()
        raise CliError(text[0] if text else type(exc).__name__) from None


def main(args: argparse.Namespace) -> int:
    if args.what == "link":
        from .calibrate_link import calibrate_link

        return calibrate_link(args, _out_path, _check_name, _backend_options, _open)
    plan = _plan(args)
    if args.dry_run:
        print(plan.describe())
        print("(--dry-run: nothing was connected, nothing moved)")
        return 0
    out = _out_path(args)
    _check_name(args.name or out.stem)
    options = _backend_options(args)
    from ..calibration import WallModel, fit_all, run_calibration
    from ..errors import CalibrationError, ConnectionLostError

    model = WallModel(plan.profile)
    connection = _open(args.backend, options)
    adapter = next(iter(connection.adapters.values()))
    where = f"{args.backend} {options.get('host', options.get('device', ''))}".strip()
    if "port" in options:
        where += f":{options['port']}"
    display = _Display(enabled=not args.quiet, plan=plan)
    print(
        f"calibrating the IR sensors of the robot on {where}: it starts touching the wall, "
        f"facing it; about {plan.duration() / 60:.0f} min; Ctrl-C stops it",
        file=sys.stderr,
        flush=True,
    )
    try:
        measurements = run_calibration(adapter, plan, model, progress=display.update)
    except KeyboardInterrupt as exc:
        display.close()
        connection.close()  # the run stopped the wheels; closing stops them once more
        print("puckboard calibrate: interrupted; the wheels were stopped", file=sys.stderr)
        partial = getattr(exc, "measurements", None)
        if partial is not None:
            _fit_what_was_measured(args, out, where, plan, partial, model, fit_all)
        return 130
    except CalibrationError as exc:
        raise CliError(f"{exc}; the wheels were stopped", status=1) from None
    except ConnectionLostError as exc:
        wheels = (
            "the wheels were stopped"
            if adapter.wheels_stopped
            else "no stop command reached the robot: check that it is not still driving"
        )
        raise CliError(
            f"the connection to the robot was lost ({exc}); {wheels}", status=1
        ) from None
    finally:
        display.close()
        connection.close()
    try:
        fits = fit_all(measurements.readings, model)
    except CalibrationError as exc:
        raise CliError(str(exc), status=1) from None
    return _write_and_report(args, out, where, plan, measurements, model, fits)


def _fit_what_was_measured(
    args: argparse.Namespace,
    out: Path,
    where: str,
    plan: CalibrationPlan,
    measurements: Measurements,
    model: WallModel,
    fit_all: Callable[[Sequence[PoseReading], WallModel], list[SensorFit]],
) -> None:
    """After Ctrl-C: fit the poses measured so far and write the profile from them, or
    say why they are too few. The stops already measured took minutes of a robot's
    time; thrown away, the whole run had to be done again."""
    from ..errors import CalibrationError

    poses = len(measurements.readings)
    try:
        fits = fit_all(measurements.readings, model)
    except CalibrationError as exc:
        print(
            f"puckboard calibrate: the {poses} poses measured are too few to fit ({exc}); "
            "nothing was written: run it again to measure more",
            file=sys.stderr,
        )
        return
    print(
        f"puckboard calibrate: fitting the {poses} of {1 + plan.stops * len(plan.presentations)} "
        "poses measured before Ctrl-C",
        file=sys.stderr,
    )
    try:
        _write_and_report(args, out, where, plan, measurements, model, fits)
    except CliError as exc:
        print(f"puckboard calibrate: error: {exc}", file=sys.stderr)


def _write_and_report(
    args: argparse.Namespace,
    out: Path,
    where: str,
    plan: CalibrationPlan,
    measurements: Measurements,
    model: WallModel,
    fits: list[SensorFit],
) -> int:
    import datetime

    from ..calibration.output import (
        ambient_light,
        calibrated_profile,
        profile_file_text,
        run_source,
    )

    when = datetime.date.today()
    name = args.name or out.stem
    try:
        profile = calibrated_profile(plan.profile, fits, name=name, when=when)
    except ValueError as exc:  # a name that is a shipped profile's, a fit out of bounds
        raise CliError(str(exc)) from None
    text = profile_file_text(
        profile,
        run_source(measurements, when, where),
        header=(
            f"{name}: measured with puckboard calibrate ir on {when.isoformat()}.",
            f"Use it: puckboard run two-robot-pass --profile {out.name}",
            f"See it: puckboard profiles show {out.name}",
        ),
    )
    out.write_text(text, encoding="utf-8")
    ambient = ambient_light(measurements, model)
    if args.json:
        data = {
            "profile_file": str(out),
            "name": name,
            "base": profile.base,
            "date": when.isoformat(),
            "backend": where,
            "seconds": measurements.seconds,
            "poses": len(measurements.readings),
            "sensors": [f.to_dict() for f in fits],
            "ambient": ambient.to_dict(),
        }
        print(json.dumps(data, indent=2))
        return 0
    print(
        f"{len(fits)} IR sensors fitted from {len(measurements.readings)} poses in "
        f"{measurements.seconds / 60:.1f} min (gain ± standard error; offset in raw units)"
    )
    print(
        f"  {'sensor':<16}{'gain':>14}{'offset':>14}{'residual RMS':>14}{'poses':>7}"
        f"{'detects up to':>15}"
    )
    for f in fits:
        reach = "always" if f.detection_end is None else f"{f.detection_end * 1000:.1f} mm"
        print(
            f"  {f.sensor:<16}{f'{f.gain:.3f} ±{f.gain_se:.3f}':>14}"
            f"{f'{f.offset:.1f} ±{f.offset_se:.1f}':>14}{f.rms:>14.1f}{f.points:>7d}{reach:>15}"
        )
    print(ambient.describe())
    print(f"wrote {out} (base {profile.base}); see it: puckboard profiles show {out}")
    print(f"use it: puckboard run two-robot-pass --profile {out}")
    return 0


class _Display:
    """Which stop, which sensor and how far, on stderr: one line rewritten on a terminal,
    a line per stop otherwise."""

    def __init__(self, *, enabled: bool, plan: CalibrationPlan) -> None:
        self.enabled = enabled
        self.tty = sys.stderr.isatty()
        self.t0 = time.monotonic()
        self.plan = plan
        self.last_stop = -1
        self.shown = False

    def update(self, progress: Progress) -> None:
        if not self.enabled:
            return
        if not self.tty and progress.stop == self.last_stop:
            return
        self.last_stop = progress.stop
        left = self.seconds_left(progress.stop, time.monotonic() - self.t0)
        line = (
            f"stop {progress.stop + 1}/{progress.stops}, {round(max(progress.backed, 0.0) * 1000)}"
            f" mm from touching: {progress.pose} ({progress.done + 1}/{progress.total} poses, "
            f"about {math.ceil(left / 60)} min left)"
        )
        if self.tty:
            print("\r" + line.ljust(78), end="", file=sys.stderr, flush=True)
            self.shown = True
        else:
            print(line, file=sys.stderr, flush=True)

    def seconds_left(self, stop: int, elapsed: float) -> float:
        """The plan's seconds for the stops still to come, at the pace measured over the
        stops done: later stops drive further, so the seconds per pose so far would tell
        "about 1 min" from the second stop to the last."""
        done, total = self.plan.duration(stop), self.plan.duration()
        return (total - done) * (elapsed / done if done > 0 else 1.0)

    def close(self) -> None:
        if self.shown:
            print("\r" + " " * 78 + "\r", end="", file=sys.stderr, flush=True)
            self.shown = False
