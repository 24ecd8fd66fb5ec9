"""``puckboard replay``: a recorded run, replayed in the browser or as one offline file.

``puckboard replay RUN.npz --web`` serves the web view's player for a recording made
with ``puckboard run --record RUN.npz``: play, pause, speed, a time slider, one tick at a
time with the arrow keys, the judge's events to jump to, and per robot its behaviour
tree with every layer's status, the values its layers read and its arbitration
timeline at that instant. ``--html FILE`` writes the same player as one self-contained
file that opens offline with a double click.
"""

from __future__ import annotations

import argparse
import sys

from .checks import check_port, check_writable
from .errors import CliError
from .parsing import help_text
from .web_view import add_web_arguments, serve_until_interrupted, start_web_view, web_url


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "replay",
        help="replay a recorded run in the browser (--web) or as one offline file (--html)",
        description=help_text(__doc__),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recording", metavar="RUN.npz", help="a recording ('puckboard run --record')")
    p.add_argument(
        "--html", default=None, metavar="FILE",
        help="write the player as one self-contained .html file (no server, works offline)",
    )  # fmt: skip
    add_web_arguments(p, "serve the player in the browser, until Ctrl-C (needs puckboard[web])")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..recording.recorder import load_recording

    if not args.web and not args.html:
        raise CliError(
            "say how to replay it: --web (serve the player in the browser) or --html FILE "
            "(write it as one file that opens offline)"
        )
    check_port(args.web_port, "--web-port", listen_on=args.web_host if args.web else None)
    if args.html:
        from ..web.export import HTML_SUFFIXES

        if not args.html.lower().endswith(HTML_SUFFIXES):
            raise CliError(f"--html {args.html!r}: the player is written as a .html file")
        check_writable(args.html, "--html")
    try:
        rec = load_recording(args.recording)
    except (FileNotFoundError, ValueError) as exc:
        raise CliError(str(exc)) from None
    if len(rec) == 0:
        raise CliError(f"{args.recording!r} holds no recorded cycle: there is nothing to replay")
    if args.html:
        from ..web.export import write_replay_html

        path = write_replay_html(rec, args.html)
        size = path.stat().st_size
        print(f"wrote {path} ({size / 1e6:.2f} MB): open it in a browser, offline")
    if args.web:
        from ..web.replay import serve_replay

        view = start_web_view(
            lambda: serve_replay(rec, host=args.web_host, port=args.web_port), args
        )
        print(f"replay: {web_url(view, args.web_host)}  (Ctrl-C ends it)", file=sys.stderr,
              flush=True)  # fmt: skip
        serve_until_interrupted(view)
    return 0
