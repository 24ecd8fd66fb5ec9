"""``puckboard profiles``: the robot profiles, their headline numbers and their sources."""

from __future__ import annotations

import argparse
import json
import math
from typing import TYPE_CHECKING, Any

from .errors import CliError

if TYPE_CHECKING:
    from ..profile import RobotProfile


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "profiles",
        help="list the robot profiles (physical e-puck, V-REP's model) with their sources",
        description=(
            "List the robot profiles a scene, 'run --profile' or 'sweep --set robot.profile=' "
            "can use, with their headline numbers (--markdown: where each comes from). "
            "'profiles show NAME|FILE.toml' prints every number you can set "
            "(--set profile.PATH=VALUE) with its value, its plausible range and the sources; "
            "a profile file beside the shipped profile it changes. 'profiles show links' "
            "lists the links' control timing (period and latency, with their sources); "
            "'profiles show LINK' one link's."
        ),
    )
    parser.add_argument("action", nargs="?", choices=("list", "show"), default="list")
    parser.add_argument(
        "name", nargs="?", help="profile to show: a name or a profile file; or links, or a link"
    )
    parser.add_argument("--json", action="store_true", help="print JSON")
    parser.add_argument(
        "--markdown",
        action="store_true",
        help="print the Markdown table of docs/profiles.md (show: the profile's paths)",
    )
    parser.set_defaults(func=main)


def headline(profile: object) -> dict[str, Any]:
    """The numbers that tell profiles apart, in display units (mm, degrees)."""
    from ..profile import RobotProfile

    assert isinstance(profile, RobotProfile)
    ring = [math.hypot(q.x, q.y) * 1000 for q in profile.prox_poses]
    return {
        "name": profile.name,
        "aliases": list(profile.aliases),
        "wheel_radius_mm": round(profile.wheel_radius * 1000, 2),
        "axle_mm": round(profile.axle_length * 1000, 2),
        "body_radius_mm": round(profile.body_radius * 1000, 2),
        "max_wheel_speed_rad_s": round(profile.max_wheel_speed, 3),
        "ir_model": profile.prox_model,
        "ir_ring_mm": [round(min(ring), 1), round(max(ring), 1)],
        "ir_headings_deg": [round(math.degrees(q.heading), 1) for q in profile.prox_poses],
        "ir_aperture_deg": round(math.degrees(profile.prox_aperture), 1),
        "ir_detects_mm": [
            round(profile.prox_min_distance * 1000, 1),
            round(profile.prox_max_distance * 1000, 1),
        ],
        "ground_sensors_mm": [
            [round(q.x * 1000, 1), round(q.y * 1000, 1)] for q in profile.ground_poses
        ],
        "gyro": profile.has_gyro,
        "sources": dict(profile.sources),
    }


def main(args: argparse.Namespace) -> int:
    from ..profile import PROFILES

    if args.action == "show":
        return _show(args)
    if args.name:
        raise CliError("'puckboard profiles' takes no name; use 'profiles show NAME'")
    chosen = list(PROFILES.values())
    rows = [headline(p) for p in chosen]
    if args.markdown:
        print(markdown_table(chosen))
        return 0
    if args.json:
        print(json.dumps(rows, indent=2))
        return 0
    for row in rows:
        aliases = f" (also {', '.join(row['aliases'])})" if row["aliases"] else ""
        print(f"{row['name']}{aliases}")
        print(
            f"  wheels r {row['wheel_radius_mm']} mm, axle {row['axle_mm']} mm, "
            f"body r {row['body_radius_mm']} mm, max {row['max_wheel_speed_rad_s']} rad/s"
        )
        lo, hi = row["ir_detects_mm"]
        ring_lo, ring_hi = row["ir_ring_mm"]
        print(
            f"  IR: {row['ir_model']}, ring {ring_lo}-{ring_hi} mm, "
            f"aperture {row['ir_aperture_deg']}°, detects {lo}-{hi} mm, headings "
            f"{', '.join(f'{h:g}' for h in row['ir_headings_deg'])}°"
        )
    return 0


def _show(args: argparse.Namespace) -> int:
    """``profiles show NAME|FILE.toml``: every path's value, plausible range and source."""
    from ..errors import PuckboardError
    from ..profile import PROFILES, get_profile, resolve_profile
    from ..profile.links import LINKS
    from .profile_table import path_table_json, path_table_markdown, path_table_text

    if not args.name:
        raise CliError(
            f"which profile? puckboard profiles show NAME|FILE.toml ({', '.join(PROFILES)}), "
            "or links"
        )
    if args.name == "links" or args.name in LINKS:
        return _show_links(args)
    try:
        profile = get_profile(resolve_profile(args.name))
    except PuckboardError as exc:
        raise CliError(str(exc)) from None
    if args.markdown:
        print(path_table_markdown(profile))
    elif args.json:
        print(json.dumps(path_table_json(profile), indent=2))
    else:
        print(path_table_text(profile))
    return 0


def _show_links(args: argparse.Namespace) -> int:
    """``profiles show links`` (every link) or ``profiles show LINK`` (one, with sources)."""
    from ..profile.links import LINKS
    from .link_table import link_json, link_table_markdown, link_table_text

    chosen = list(LINKS.values()) if args.name == "links" else [LINKS[args.name]]
    if args.markdown:
        print(link_table_markdown())
    elif args.json:
        print(json.dumps([link_json(link) for link in chosen], indent=2))
    else:
        print(link_table_text(chosen, sources=args.name != "links"))
    return 0


#: Rows of the sources table: (label, how to show the value, key in ``sources``).
_TABLE_ROWS: tuple[tuple[str, str, str], ...] = (
    ("wheel radius", "{wheel_radius_mm} mm", "wheel_radius"),
    ("axle", "{axle_mm} mm", "axle_length"),
    ("body radius", "{body_radius_mm} mm", "body_radius"),
    ("wheel speed limit", "{max_wheel_speed_rad_s} rad/s", "max_wheel_speed"),
    ("IR model", "{ir_model}", "prox_model"),
    ("IR poses", "ring {ir_ring_mm[0]}-{ir_ring_mm[1]} mm", "prox_poses"),
    ("IR aperture", "{ir_aperture_deg}°", "prox_aperture"),
    ("IR detects", "{ir_detects_mm[0]}-{ir_detects_mm[1]} mm", "prox_max_distance"),
    ("ground sensors", "x {ground_sensors_mm[1][0]} mm", "ground_poses"),
    ("camera", "", "camera"),
)


def markdown_table(profiles: list[RobotProfile]) -> str:
    """One row per model number, one column per profile: the value and where it comes from.

    docs/profiles.md holds this table verbatim, and a test keeps the two in step.
    """
    rows = [headline(p) for p in profiles]
    lines = [
        "| | " + " | ".join(f"`{r['name']}`" for r in rows) + " |",
        "|---|" + "---|" * len(rows),
    ]
    for label, shown, key in _TABLE_ROWS:
        cells = []
        for profile, row in zip(profiles, rows):
            value = shown.format(**row)
            source = profile.sources.get(key, "")
            if key == "prox_max_distance" and "prox_min_distance" in profile.sources:
                source = f"{profile.sources['prox_min_distance']}; {source}"
            # a source that starts with its number already shows the value
            starts_with_number = source[:1].isdigit()
            cells.append(source if starts_with_number or not value else f"{value}; {source}")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)
