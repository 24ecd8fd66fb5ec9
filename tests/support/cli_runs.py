"""A ``puckboard`` command run as a reader runs it in a folder of theirs, but in this
process: the CLI's own ``main``, which the console script calls.

Starting an interpreter per command costs more than most commands themselves; tests
whose subject is what a command prints or writes run it here. Tests whose subject is
the process itself (the console script, exit status on a signal, Ctrl-C) start one.
"""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Sequence
from pathlib import Path

__all__ = ["run_in"]


def run_in(folder: Path, argv: Sequence[str]) -> tuple[int, str]:
    """``puckboard ARGV`` run in ``folder``: its exit status and what it printed on stdout."""
    from puckboard.cli import main

    printed = io.StringIO()
    before = Path.cwd()
    os.chdir(folder)
    try:
        with contextlib.redirect_stdout(printed):
            try:
                status = main(list(argv))
            except SystemExit as exc:  # argparse's --version and --help end this way
                status = exc.code if isinstance(exc.code, int) else 1
    finally:
        os.chdir(before)
    return status, printed.getvalue()
