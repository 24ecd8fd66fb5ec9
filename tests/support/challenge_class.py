"""A small class for the challenge tests: the shipped controllers' factories and one
broken submission of every kind grading must survive, on a challenge cut short enough
for a test (two graded cells of two episodes, a five-second pre-flight limit).

The class is graded once per test session (:func:`graded_class`), by the first test
worker that asks; tests that change the output folder work on a copy.
"""

from __future__ import annotations

import json
from pathlib import Path

CHALLENGE = """
name = "test-pass"
title = "The pass, for the tests"
description = "Two cells of the pass, two episodes each."
[limits]
episode_timeout = 60
check_timeout = 5
memory_mib = 256
[ranking]
baselines = ["stock"]
[practice]
seeds = "0:1"
[[practice.cells]]
name = "line"
scene = "line-follow"
duration = 3
[graded]
episodes = 2
[[graded.cells]]
name = "pass"
scene = "two-robot-pass"
[[graded.cells]]
name = "bend"
scene = "two-robot-pass-bend"
profile = "epuck"
variation = "plausible"
"""

SECRET = "the lecturer's own words"

_SHIPPED = (
    "from puckboard.behaviours import {0}\ndef make_controller(**params):\n"
    "    return {0}(**params)\n"
)

_LAYER = """
import os, sys, time
from puckboard.behaviours import Controller, Cruise

class Broken(Cruise):
    def command(self, frame):
        if frame.time > 0.5:
            {what}
        return super().command(frame)

def make_controller(**params):
    return Controller([Broken()], name="broken")
"""

#: name -> (the file's text, the verdict it must get)
SUBMISSIONS: dict[str, tuple[str, str]] = {
    "robust_one": (_SHIPPED.format("robust"), "graded"),
    "improved_one": (_SHIPPED.format("improved"), "graded"),
    "stock_one": (_SHIPPED.format("stock"), "graded"),
    "printer": (
        _SHIPPED.format("stock").replace("    return", "    print('hello')\n    return"),
        "graded",
    ),
    "writer": (
        _SHIPPED.format("stock").replace(
            "    return", "    open('notes.txt', 'w').write('mine')\n    return"
        ),
        "graded",
    ),
    "not_python": ("def make_controller(:\n    pass\n", "not-python"),
    "no_import": ("import no_such_module_anywhere\n", "import-failed"),
    "no_factory": ("def build():\n    return None\n", "no-factory"),
    "wrong_return": ("def make_controller(**params):\n    return 42\n", "wrong-return"),
    "raises": (_LAYER.format(what="raise RuntimeError('my layer broke')"), "layer-raised"),
    "sleeps": (_LAYER.format(what="time.sleep(3600)"), "timeout"),
    "loops": (_LAYER.format(what="while True: pass"), "timeout"),
    "sys_exit": ("import sys\ndef make_controller(**params):\n    sys.exit(3)\n", "exited"),
    "os_exit": (_LAYER.format(what="os._exit(5)"), "exited"),
    "hog": (
        _LAYER.format(what="self.__dict__.setdefault('kept', []).append(bytearray(8_000_000))"),
        "memory",
    ),
}


def write_class(folder: Path) -> tuple[Path, Path]:
    """The challenge file and the submissions folder, written into ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    challenge = folder / "test-pass.toml"
    challenge.write_text(CHALLENGE, encoding="utf-8")
    submissions = folder / "class"
    submissions.mkdir(exist_ok=True)
    for name, (text, _) in SUBMISSIONS.items():
        (submissions / f"{name}.py").write_text(text, encoding="utf-8")
    return challenge, submissions


def graded_class() -> dict[str, str]:
    """The class graded once per session: paths of the challenge, the submissions, the
    output folder, and the grading's JSON and what it printed."""
    import os
    import tempfile

    import session_cache

    def compute() -> dict[str, str]:
        import contextlib
        import io

        from puckboard.cli import main

        # in the session's folder (removed when the session ends), else a temporary one
        folder = Path(tempfile.mkdtemp(prefix="challenge-", dir=os.environ.get(session_cache.ENV)))
        challenge, submissions = write_class(folder)
        (folder / "secret.txt").write_text(SECRET + "\n", encoding="utf-8")
        out, err = io.StringIO(), io.StringIO()
        argv = [
            "challenge", "grade", str(challenge), str(submissions), "--secret-file",
            str(folder / "secret.txt"), "--out", str(folder / "results"), "--workers", "2",
            "--json",
        ]  # fmt: skip
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(argv)
        return {
            "folder": str(folder),
            "challenge": str(challenge),
            "submissions": str(submissions),
            "out": str(folder / "results"),
            "status": str(status),
            "json": out.getvalue(),
            "stderr": err.getvalue(),
        }

    return session_cache.once("challenge-class", compute)


def rows_of(grading: dict[str, str]) -> list[dict[str, object]]:
    return list(json.loads(grading["json"])["rows"])
