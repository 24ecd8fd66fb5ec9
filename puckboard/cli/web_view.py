"""The web view a command serves beside its work (``run``, ``serve``, ``replay``): its
options, its start in one line on failure, the address to share, and keeping it up."""

from __future__ import annotations

import argparse
import socket
from collections.abc import Callable
from typing import TYPE_CHECKING

from .bind import bind_error_message
from .errors import CliError, missing_extra

if TYPE_CHECKING:
    from ..web.server import WebView

__all__ = ["add_web_arguments", "serve_until_interrupted", "start_web_view", "web_url"]


def add_web_arguments(parser: argparse.ArgumentParser, web_help: str | None = None) -> None:
    """``--web``, ``--web-host`` and ``--web-port``, the same for ``run``, ``serve`` and
    ``replay`` (``web_help`` says what ``--web`` serves, when not a live view)."""
    parser.add_argument(
        "--web", action="store_true",
        help=web_help
        or "also serve a live view of the simulation in the browser (needs puckboard[web])",
    )  # fmt: skip
    parser.add_argument(
        "--web-host", default="127.0.0.1", metavar="HOST",
        help="address of the web view (default 127.0.0.1, this machine only; 0.0.0.0 for a "
        "class)",
    )  # fmt: skip
    parser.add_argument(
        "--web-port", type=int, default=8080, metavar="PORT",
        help="port of the web view (default 8080; 0 = any free port)",
    )  # fmt: skip


def start_web_view(start: Callable[[], WebView], args: argparse.Namespace) -> WebView:
    """Start a web view with ``start()``; a missing aiohttp or a taken port is one line."""
    try:
        return start()
    except ImportError as exc:
        raise missing_extra(exc, "--web") from None
    except OSError as exc:
        raise CliError(
            bind_error_message(exc, args.web_host, args.web_port, "--web-port")
        ) from None


def web_url(view: WebView, host: str) -> str:
    """The URL to share: on every interface, the machine's name stands in for 0.0.0.0."""
    if host in ("0.0.0.0", "*", "::"):
        return f"http://{socket.gethostname()}:{view.port}/  (or this machine's address)"
    return str(view.url)


def serve_until_interrupted(view: WebView) -> None:
    """Keep a web view up (its page, its verdict) until Ctrl-C, then close it; the
    Ctrl-C goes on to :func:`puckboard.cli.main`, which ends the command with status 130
    as every command ends on Ctrl-C."""
    import time

    try:
        while True:
            time.sleep(0.5)
    finally:
        view.close()
