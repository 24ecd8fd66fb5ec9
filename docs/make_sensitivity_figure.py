"""Measure the flagship sensitivity analysis and draw docs/img/sensitivity-two-robot-pass.png.

::

    python docs/make_sensitivity_figure.py [WORKDIR]      # default WORKDIR: ./sensitivity-work

It runs, in WORKDIR, exactly the command docs/controllers.md gives::

    puckboard sensitivity two-robot-pass --controller improved
        --controller my_controller.py:my_controller --profile epuck --profile epuck-vrep
        --seeds 0:40 --out flagship.csv --plot sensitivity-two-robot-pass.png

with ``my_controller.py`` saved from the tutorial's block, as a reader saves it, and
copies the figure into docs/img/. Every episode is kept in ``WORKDIR/flagship.csv``, so
an interrupted run resumes (run it again) and a finished one redraws in seconds; the
report is written to ``WORKDIR/report.txt``. The whole analysis is 8,720 episodes, about
25 minutes on two cores (docs/simulator.md gives the measured time). Needs the ``viz``
extra (matplotlib).
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shutil
import sys
from pathlib import Path

from puckboard.cli import main as puckboard

DOCS = Path(__file__).resolve().parent
FIGURE = "sensitivity-two-robot-pass.png"
COMMAND = [
    "sensitivity", "two-robot-pass",
    "--controller", "improved", "--controller", "my_controller.py:my_controller",
    "--profile", "epuck", "--profile", "epuck-vrep",
    "--seeds", "0:40", "--out", "flagship.csv", "--plot", FIGURE,
]  # fmt: skip


def save_tutorial_controller(folder: Path) -> None:
    """``my_controller.py`` as the tutorial has the reader save it (step 6)."""
    page = (DOCS / "tutorial.md").read_text(encoding="utf-8")
    (block,) = re.findall(r"^```python\n(# my_controller\.py\n.*?)^```", page, re.M | re.S)
    (folder / "my_controller.py").write_text(block, encoding="utf-8")


def main(argv: list[str]) -> int:
    work = Path(argv[0] if argv else "sensitivity-work").resolve()
    work.mkdir(parents=True, exist_ok=True)
    save_tutorial_controller(work)
    os.chdir(work)  # the controller spec is relative, as in the page's command
    report = io.StringIO()
    with contextlib.redirect_stdout(report):
        status = puckboard(COMMAND)
    (work / "report.txt").write_text(report.getvalue(), encoding="utf-8")
    print(report.getvalue())
    if status != 0:
        return status
    shutil.copyfile(work / FIGURE, DOCS / "img" / FIGURE)
    print(f"wrote docs/img/{FIGURE}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
