"""``puckboard tree``: draw a controller's behaviour tree (text, dot, PNG or SVG)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .checks import check_writable
from .errors import CliError, controller_error
from .parsing import OneController

FORMATS = ("ascii", "unicode", "dot", "png", "svg")


def register(subparsers: argparse._SubParsersAction) -> None:
    p = subparsers.add_parser(
        "tree",
        help="draw a controller's behaviour tree",
        description=(
            "Draw a controller's behaviour tree: its layers in priority order (1 = highest) "
            "and the blackboard keys each reads. Text formats print to the terminal; "
            "png and svg need Graphviz's 'dot' program."
        ),
    )
    p.add_argument(
        "--controller",
        action=OneController,
        default="improved",
        metavar="SPEC",
        help="stock, improved, robust, MODULE:FACTORY or path/file.py:FACTORY (default: improved)",
    )
    p.add_argument(
        "--format",
        choices=FORMATS,
        default=None,
        help="output format (default: from -o's suffix, else unicode)",
    )
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..behaviours import load_controller
    from ..viz.tree import GraphvizMissingError, render_tree

    fmt = args.format
    out = Path(args.output) if args.output else None
    if fmt is None:
        suffix = out.suffix.lower().lstrip(".") if out is not None else ""
        fmt = {"txt": "unicode", "gv": "dot"}.get(suffix, suffix) if suffix else "unicode"
        if fmt not in FORMATS:
            raise CliError(f"cannot tell the format from {args.output!r}; pass --format")
    if fmt == "png" and out is None:
        raise CliError("PNG is binary: give a file with -o tree.png")
    if out is not None:
        check_writable(out, "-o")
    try:
        controller = load_controller(args.controller)
    except Exception as exc:
        shown = controller_error(exc, args.controller)
        if shown is not None:
            raise shown from None
        raise
    try:
        result = render_tree(controller, fmt)
    except GraphvizMissingError as exc:
        raise CliError(str(exc)) from exc
    if out is None:
        assert isinstance(result, str)
        sys.stdout.write(result if result.endswith("\n") else result + "\n")
        return 0
    try:
        if isinstance(result, bytes):
            out.write_bytes(result)
        else:
            out.write_text(result, encoding="utf-8")
    except OSError as exc:  # the file itself is read-only, or the disk is full
        raise CliError(f"-o {str(out)!r}: cannot write it ({exc.strerror or exc})") from None
    print(f"wrote {out}")
    return 0
