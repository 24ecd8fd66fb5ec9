"""Reading the pages' code and the output they show, and comparing it with a real run.

A page that shows what a command or a block prints makes a promise a reader checks
character by character, so the docs tests compare it exactly: every number included,
because the runs are seeded. Only what the wall clock decides is masked (how long a run
took, its real-time factor, dates, temporary paths). A shown line ``...`` stands for any
number of printed lines, for outputs too long to show whole; it is the only elision.
"""

from __future__ import annotations

import re

__all__ = ["assert_shown", "fences", "mask_wall_clock"]

FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", re.MULTILINE | re.DOTALL)

#: (pattern, replacement): the parts of an output the wall clock decides.
WALL_CLOCK = (
    # "69.5 s simulated in 0.40 s (174x real time, ..." (puckboard run's header)
    (re.compile(r"simulated in [\d.]+ s \([\d,.]+x real time"), "simulated in <s> (<x> real time"),
    # "60 of 60 episodes (60 run, 0 already in runs.csv), 7.6 s" (puckboard sweep's header)
    (re.compile(r"(episodes \([^)]*\)), [\d.]+ s$", re.MULTILINE), r"\1, <s>"),
    # "... episodes (32 run), 3.5 s, 9.0 episodes/s" (puckboard sensitivity's header;
    # transfer's goes on: "...; seeds 400:404 at every model")
    (
        re.compile(r"(episodes \([^)]*\)), [\d.]+ s, [\d.]+ episodes/s(?=$|;)", re.MULTILINE),
        r"\1, <s>, <rate>",
    ),
    (re.compile(r"\b\d{4}-\d{2}-\d{2}([T ]\d{2}:\d{2}(:\d{2}(\.\d+)?)?)?\b"), "<date>"),
    (
        re.compile(r"(/tmp|/var/folders|[A-Z]:\\Users\\[^\\]+\\AppData\\Local\\Temp)[^\s'\"]*"),
        "<tmp>",
    ),
)


def fences(text: str) -> list[tuple[str, str]]:
    """The page's fenced blocks in order, as (language, body)."""
    return [(m.group(1), m.group(2)) for m in FENCE.finditer(text)]


def mask_wall_clock(text: str) -> str:
    """``text`` with the wall-clock figures replaced by placeholders."""
    for pattern, replacement in WALL_CLOCK:
        text = pattern.sub(replacement, text)
    return text


def _lines(text: str) -> list[str]:
    lines = [line.rstrip() for line in mask_wall_clock(text).splitlines()]
    while lines and not lines[0]:
        lines.pop(0)
    while lines and not lines[-1]:
        lines.pop()
    return lines


def assert_shown(shown: str, printed: str, where: str) -> None:
    """The output a page shows is what was printed, line for line, numbers included;
    a shown ``...`` line matches any run of printed lines (at least one)."""
    want, got = _lines(shown), _lines(printed)
    if not _match(want, got):
        raise AssertionError(
            f"{where}: the page shows\n"
            + "\n".join(want)
            + "\n\nthe run printed\n"
            + "\n".join(got)
        )


def _match(want: list[str], got: list[str]) -> bool:
    if not want:
        return not got
    if want[0].strip() == "...":
        return any(_match(want[1:], got[k:]) for k in range(1, len(got) + 1))
    return bool(got) and want[0] == got[0] and _match(want[1:], got[1:])
