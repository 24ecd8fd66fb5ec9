"""``puckboard calibrate link``: time a robot's link and write the ``[link]`` table.

Kept apart from ``calibrate ir`` (:mod:`.calibrate`), whose argument checks and backend
opening it shares, since the two measure unrelated things.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .errors import CliError


def calibrate_link(
    args: argparse.Namespace,
    out_path: Callable[[argparse.Namespace], Path],
    check_name: Callable[[str], None],
    backend_options: Callable[[argparse.Namespace], dict[str, Any]],
    open_backend: Callable[[str, dict[str, Any]], Any],
) -> int:
    """Measure, report, write; one-line errors, the wheels zero however it ends. The
    ``--out`` file is checked before the robot is reached, the measured spreads are
    printed whatever becomes of the write, and Ctrl-C keeps the cycles timed."""
    from ..calibration.link import LinkInterrupted, check_link_target, measure_link
    from ..errors import ConnectionLostError, PuckboardError
    from ..profile import get_profile, resolve_profile
    from ..sweep.progress import make_progress

    if args.rounds < 2:
        raise CliError(f"--rounds must be at least 2 (a spread needs two), got {args.rounds}")
    if args.dry_run:
        print(_plan_text(args))
        print("(--dry-run: nothing was connected, nothing moved)")
        return 0
    out = out_path(args)
    name = args.name or out.stem
    try:
        if out.exists():
            check_link_target(out)  # its [link] is replaced or added: it must be a profile
        else:
            check_name(name)
        base = get_profile(resolve_profile(args.profile))
    except PuckboardError as exc:
        raise CliError(f"{exc}; nothing was measured") from None
    options = backend_options(args)
    where = f"{args.backend} {options.get('host', options.get('device', ''))}".strip()
    if "port" in options:
        where += f":{options['port']}"
    connection = open_backend(args.backend, options)
    adapter = next(iter(connection.adapters.values()))
    print(
        f"timing {args.rounds} control cycles over {where} (the wheels stay at zero)",
        file=sys.stderr,
        flush=True,
    )
    progress = make_progress(enabled=not args.quiet, label="calibrate link", unit="cycles")
    progress.start(args.rounds)
    try:
        measured = measure_link(adapter, args.rounds, progress=lambda k, n: progress.advance(1))
    except LinkInterrupted as exc:
        progress.close()
        connection.close()
        if exc.measured is None:
            print(
                f"puckboard calibrate: interrupted after {exc.cycles} cycles, too few for a "
                "spread (2 at least); nothing was written",
                file=sys.stderr,
            )
            return 130
        print(
            f"puckboard calibrate: interrupted; keeping the {exc.cycles} of {args.rounds} "
            "cycles timed before Ctrl-C",
            file=sys.stderr,
        )
        try:
            _report_and_write(args, out, where, base, name, exc.measured, exc.cycles)
        except CliError as error:
            print(f"puckboard calibrate: error: {error}", file=sys.stderr)
        return 130
    except ConnectionLostError as exc:
        raise CliError(f"the connection to the robot was lost ({exc})", status=1) from None
    finally:
        progress.close()
        connection.close()
    return _report_and_write(args, out, where, base, name, measured, args.rounds)


def _plan_text(args: argparse.Namespace) -> str:
    """What ``calibrate link`` would do, for ``--dry-run``."""
    over = f"--backend {args.backend}" if args.backend else "the robot's link (--backend)"
    out = args.out or "the --out FILE.toml"
    return (
        f"calibrate link: time {args.rounds} control cycles over {over}, each reading every "
        "sensor and commanding the wheels to zero (the robot does not move); then write "
        "the period (the 95th percentile of a cycle) and the latency (the median round "
        f"trip) into the [link] table of {out} (created, or updated in place), and print "
        "both spreads"
    )


def _report_and_write(
    args: argparse.Namespace,
    out: Path,
    where: str,
    base: Any,
    name: str,
    measured: Any,
    cycles: int,
) -> int:
    """Print what was measured, then write it: a write that fails loses nothing printed
    (status 1, the file as it was)."""
    import datetime

    from ..calibration.link import write_link_table
    from ..errors import PuckboardError

    when = datetime.date.today().isoformat()
    source = f"puckboard calibrate link: {cycles} cycles over {where}, {when}"
    try:
        write_link_table(out, measured, source, base=base.base or base.name, name=name)
        failed = None
    except (PuckboardError, OSError) as exc:
        failed = CliError(f"{out}: not updated ({exc}); the measurement is printed above", status=1)
    if args.json:
        data = {
            "profile_file": None if failed else str(out),
            "backend": where,
            "period_s": round(measured.period, 6),
            "latency_s": round(measured.latency, 6),
            "round_trip_s": measured.round_trip.to_dict(),
            "cycle_s": measured.cycle.to_dict(),
        }
        print(json.dumps(data, indent=2))
    else:
        rt, cy = measured.round_trip, measured.cycle
        print(
            f"round trip (sense): median {rt.median * 1e3:.1f} ms, 5-95 % "
            f"{rt.p5 * 1e3:.1f}-{rt.p95 * 1e3:.1f} ms, at most {rt.max * 1e3:.1f} ms"
        )
        print(
            f"whole cycle (sense, command): median {cy.median * 1e3:.1f} ms, 95 % "
            f"{cy.p95 * 1e3:.1f} ms, at most {cy.max * 1e3:.1f} ms"
        )
        if failed is None:
            print(
                f"wrote [link] period = {measured.period * 1e3:.1f} ms, latency = "
                f"{measured.latency * 1e3:.1f} ms to {out}"
            )
            print(f"use it: puckboard run two-robot-pass --profile {out}")
    if failed is not None:
        raise failed
    return 0
