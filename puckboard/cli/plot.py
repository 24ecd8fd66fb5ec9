"""``puckboard plot``: plots (and animations) of a recorded run."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from .checks import check_writable
from .errors import CliError


def register(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser(
        "plot",
        help="plot a recorded run (trajectories, arbitration, sensors, wheels)",
        description=(
            "Plot a run recorded with 'puckboard run --record run.npz': trajectories, "
            "the arbitration timeline (which layer had control when), sensor traces and "
            "wheel commands. --animate renders a GIF or MP4 from the recording instead "
            "(the plots too when --out is given)."
        ),
    )
    p.add_argument("recording", metavar="RECORDING", help="a .npz recording")
    p.add_argument(
        "--out", default=None, metavar="DIR",
        help="folder for the plots (default: .; with --animate, plots only when --out is given)",
    )  # fmt: skip
    p.add_argument("--format", choices=("png", "svg"), default="png", help="image format")
    p.add_argument(
        "--animate", metavar="FILE", default=None, help="write an animation (.gif or .mp4)"
    )
    p.add_argument(
        "--speed",
        type=float,
        default=None,
        help="playback speed: times real time (default: 4 for --animate, 1 for --view)",
    )
    p.add_argument("--fps", type=float, default=10.0, help="animation frames per second")
    p.add_argument(
        "--from",
        dest="start",
        type=float,
        default=None,
        metavar="S",
        help="animate from S seconds of run time",
    )
    p.add_argument(
        "--to",
        dest="end",
        type=float,
        default=None,
        metavar="S",
        help="animate up to S seconds of run time",
    )
    p.add_argument(
        "--view",
        action="store_true",
        help="replay the run in a window (space: pause, n: step, +/-: speed)",
    )
    p.add_argument(
        "--size", default=None, metavar="WxH", help="animation size in pixels, e.g. 800x450"
    )
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Check every option, then write: a bad --from/--to or --size found after the plots
    were written would leave half the outputs behind and the user unsure which."""
    from ..recording.recorder import load_recording
    from ..viz.animation import (
        VideoSupportError,
        check_animation_path,
        frame_indices,
        render_animation,
    )
    from ..viz.plots import save_plots

    _check_window(args.start, args.end)
    try:
        rec = load_recording(args.recording)
    except (FileNotFoundError, ValueError) as exc:
        raise CliError(str(exc)) from None
    if args.animate:
        try:
            check_animation_path(args.animate)
        except (ValueError, VideoSupportError) as exc:
            raise CliError(str(exc)) from exc
    if (args.speed is not None and args.speed <= 0) or args.fps <= 0:
        raise CliError("--speed and --fps must be positive")
    if args.animate:
        try:  # the window against the run's own span, before any file is written
            frame_indices(rec, args.fps, args.speed or 4.0, args.start, args.end)
        except ValueError as exc:
            raise CliError(str(exc)) from None
    size = None
    if args.size:
        try:
            w, h = (int(v) for v in args.size.lower().split("x"))
        except ValueError:
            raise CliError(f"--size must look like 800x450, got {args.size!r}") from None
        from ..viz.animation import check_size

        try:
            size = check_size(w, h)
        except ValueError as exc:
            raise CliError(f"--{exc}") from None
    # last of the checks (they create a missing folder), before anything is shown or written
    if args.out is not None:
        check_writable(args.out, "--out", folder=True)
    if args.animate:
        check_writable(args.animate, "--animate")
    if args.view:
        from ..viz.live import can_show, replay

        if not can_show():
            raise CliError("--view needs a display; use --animate run.gif instead")
        replay(rec, speed=args.speed or 1.0)
        if not (args.out or args.animate):
            return 0
    # an animation alone writes only itself: the plots it used to write besides went
    # into the current folder unasked, over any plots already there
    if args.out or not args.animate:
        out = Path(args.out) if args.out else Path(".")
        try:
            paths = save_plots(rec, out, args.format)
        except ValueError as exc:
            raise CliError(str(exc)) from exc
        for path in paths:
            print(f"wrote {path}")
    if args.animate:
        bar = _FrameProgress()
        try:
            info = render_animation(
                rec, args.animate, fps=args.fps, speed=args.speed or 4.0, size=size,
                start=args.start, end=args.end, progress=bar,
            )  # fmt: skip
        except ValueError as exc:
            raise CliError(str(exc)) from exc
        finally:
            bar.close()
        w, h = info["size"]
        print(
            f"wrote {info['path']} ({info['frames']} frames, {w}x{h}, {info['bytes'] / 1e6:.1f} MB)"
        )
    return 0


class _FrameProgress:
    """Frames rendered, on stderr (a long animation is minutes of silence otherwise)."""

    def __init__(self) -> None:
        from ..sweep.progress import make_progress

        self.bar = make_progress(label="plot --animate", unit="frames")
        self.started = False

    def __call__(self, done: int, total: int) -> None:
        if not self.started:
            self.bar.start(total)
            self.started = True
        self.bar.advance(1)

    def close(self) -> None:
        if self.started:
            self.bar.close()


def _check_window(start: float | None, end: float | None) -> None:
    """``--from``/``--to`` must be finite times in order: ``nan`` would silently mean
    "from the start" and a reversed window can only fail, after the plots are written."""
    for flag, value in (("--from", start), ("--to", end)):
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise CliError(f"{flag} must be a finite number of seconds ≥ 0, got {value:g}")
    if start is not None and end is not None and end < start:
        raise CliError(f"--to ({end:g} s) is before --from ({start:g} s); swap them")
