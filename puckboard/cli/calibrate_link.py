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

from .common import CliError


def calibrate_link(
    args: argparse.Namespace,
    out_path: Callable[[argparse.Namespace], Path],
    check_name: Callable[[str], None],
    backend_options: Callable[[argparse.Namespace], dict[str, Any]],
    open_backend: Callable[[str, dict[str, Any]], Any],
) -> int:
    """Measure, write, report; one-line errors, the wheels zero however it ends."""
    import datetime

    from ..calibration.link import measure_link, write_link_table
    from ..errors import ConnectionLostError, PuckboardError
    from ..profile import get_profile, resolve_profile

    if args.rounds < 2:
        raise CliError(f"--rounds must be at least 2 (a spread needs two), got {args.rounds}")
    out = out_path(args)
    name = args.name or out.stem
    if not out.exists():
        check_name(name)
    try:
        base = get_profile(resolve_profile(args.profile))
    except PuckboardError as exc:
        raise CliError(str(exc)) from None
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
    try:
        measured = measure_link(adapter, args.rounds)
    except KeyboardInterrupt:
        connection.close()
        print("puckboard calibrate: interrupted; nothing was written", file=sys.stderr)
        return 130
    except ConnectionLostError as exc:
        raise CliError(f"the connection to the robot was lost ({exc})", status=1) from None
    finally:
        connection.close()
    when = datetime.date.today().isoformat()
    source = f"puckboard calibrate link: {args.rounds} cycles over {where}, {when}"
    try:
        write_link_table(out, measured, source, base=base.base or base.name, name=name)
    except PuckboardError as exc:
        raise CliError(f"{out}: not updated: {exc}") from None
    if args.json:
        data = {
            "profile_file": str(out),
            "backend": where,
            "period_s": round(measured.period, 6),
            "latency_s": round(measured.latency, 6),
            "round_trip_s": measured.round_trip.to_dict(),
            "cycle_s": measured.cycle.to_dict(),
            "repeated": round(measured.repeated, 4),
        }
        print(json.dumps(data, indent=2))
        return 0
    rt, cy = measured.round_trip, measured.cycle
    print(
        f"round trip (sense): median {rt.median * 1e3:.1f} ms, 90 % {rt.p90 * 1e3:.1f} ms, "
        f"5-95 % {rt.p5 * 1e3:.1f}-{rt.p95 * 1e3:.1f} ms, at most {rt.max * 1e3:.1f} ms"
    )
    print(
        f"repeated readings: {measured.repeated:.0%} of cycles brought no new packet (every "
        "sensor value as in the cycle before)"
    )
    print(
        f"whole cycle (sense, command): median {cy.median * 1e3:.1f} ms, 95 % "
        f"{cy.p95 * 1e3:.1f} ms, at most {cy.max * 1e3:.1f} ms"
    )
    print(
        f"wrote [link] period = {measured.period * 1e3:.1f} ms, latency = "
        f"{measured.latency * 1e3:.1f} ms, the round trips' distribution and the repeated "
        f"share to {out}"
    )
    print(f"use it: puckboard run two-robot-pass --profile {out}")
    return 0
