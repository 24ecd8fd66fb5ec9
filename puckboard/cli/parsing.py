"""How every subcommand's parser reads its options: one line for a refusal, an option
of one value given once, and the arguments several commands share (``--variation``).

Subcommand modules import from here and the other shared modules, never from the
package's ``__init__`` (which imports them to build the parser), so nothing in the
command line runs back up.
"""

from __future__ import annotations

import argparse
import re
from typing import Any, NoReturn

from .errors import CliError

__all__ = ["OneController", "VariationName", "add_variation_argument", "help_text"]


def help_text(docstring: str | None) -> str:
    """A module docstring as ``--help`` shows it: reST's ``double backticks`` become
    'quotes', which read as code in a terminal where backticks are noise."""
    return re.sub(r"``(.+?)``", r"'\1'", docstring or "", flags=re.S)


class _ArgumentError(CliError):
    """A value argparse refused in a subcommand's options (``prog`` is ``puckboard CMD``)."""

    def __init__(self, prog: str, message: str) -> None:
        super().__init__(message)
        self.prog = prog


class _StoreOnce(argparse._StoreAction):
    """An option of one value, refused when given twice (``--seed 7 --seed 8``): argparse
    would keep the last without a word, and which one was meant only the user knows."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        given = vars(namespace).setdefault("_given_once", {})
        if option_string is not None and self.dest in given:
            shown = self.option_strings[-1]
            parser.error(f"{shown} given twice ({given[self.dest]}, then {values}); give it once")
        given[self.dest] = values
        setattr(namespace, self.dest, values)


class _SubcommandParser(argparse.ArgumentParser):
    """A subcommand's parser whose refusals end like every other bad input: one line
    ``puckboard CMD: error: ...`` and status 2 from :func:`main`, not argparse's usage
    block and ``SystemExit``; ``puckboard CMD --help`` still shows the usage. An option
    of one value given twice is refused (:class:`_StoreOnce`)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        # argument groups share these, so every plain option of the subcommand is one
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)
        # A value that starts with a minus and a digit ('--seeds -5:2', '--distance
        # -5mm') is a value, not an option: argparse alone takes only plain numbers
        # ('-5', '-0.5') so, and refuses the rest with "expected one argument", which
        # hides the check that would say what is wrong with the value. No option of
        # puckboard starts with a digit.
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message: str) -> NoReturn:
        flag, sep, detail = message.partition(": ")
        if sep and flag.startswith("argument ") and detail.startswith(flag[9:] + " "):
            message = detail  # the type's message names the option already (seed_type)
        raise _ArgumentError(self.prog, message)


class OneController(argparse.Action):
    """``--controller`` of a command that runs one controller: given twice it is refused
    (argparse would keep the last and run it without a word), pointing to ``sweep``,
    which runs several side by side."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        seen = "_controller_given"
        if getattr(namespace, seen, None) is not None:
            first = getattr(namespace, seen)
            parser.error(
                f"--controller given twice ({first}, then {values}); "
                f"{parser.prog} takes one controller: run it once per controller, or compare "
                f"them with puckboard sweep SCENE --controller {first} --controller {values}"
            )
        setattr(namespace, seen, values)
        setattr(namespace, self.dest, values)


class VariationName(argparse.Action):
    """``--variation NAME``: a name of the variations' registry (an installed package's
    too), refused in one line otherwise; ``variation_given`` notes that it was given."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        from ..scenario.variation import check_variation

        try:
            setattr(namespace, self.dest, check_variation(str(values)))
        except ValueError as exc:
            parser.error(f"--variation: {exc}")
        namespace.variation_given = True


def settings_help() -> str:
    """The settings ``--set`` takes, named and with their units as the one table
    (:mod:`puckboard.scenario.settings`) has them, so a help text never lists a setting
    that is not there or misses one that is."""
    from ..scenario.settings import SETTINGS

    return ", ".join(
        s.name if s.unit == "1" else f"{s.name} ({s.unit_text()})" for s in SETTINGS.values()
    )


def add_variation_argument(parser: argparse.ArgumentParser, seeded_by: str = "--seed") -> None:
    """``--variation NAME`` (the variations' registry, :mod:`puckboard.scenario.variation`),
    the same for ``run``, ``sweep``, ``tune`` and ``serve``; ``seeded_by`` is the option
    that seeds the draw (``sweep`` has ``--seeds``)."""
    from ..scenario.variation import NONE, VARIATIONS

    listed = "; ".join(f"{v.name}: {v.help}" for v in VARIATIONS.values() if v is not NONE)
    parser.add_argument(
        "--variation",
        action=VariationName,
        default=NONE.name,
        metavar="NAME",
        help=f"how each robot (and world) is drawn, seeded by {seeded_by}: {listed}; default "
        f"{NONE.name}: {NONE.help} (an installed package may add variations)",
    )
