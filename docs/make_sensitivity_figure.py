"""Measure the flagship sensitivity analysis and draw docs/img/sensitivity-two-robot-pass.png
(or, with ``--joint``, the joint method's docs/img/sensitivity-joint-two-robot-pass.png).

::

    python docs/make_sensitivity_figure.py [WORKDIR]      # default WORKDIR: ./sensitivity-work
    python docs/make_sensitivity_figure.py --joint [WORKDIR]

``--joint`` runs the same controllers and profiles by ``--method joint --seeds 0:300``
(1,200 episodes, ``flagship-joint.parquet``); docs/sweeps.md compares the two figures.

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

JOINT_FIGURE = "sensitivity-joint-two-robot-pass.png"
JOINT_COMMAND = [
    *COMMAND[:10], "--method", "joint", "--seeds", "0:300", "--out", "flagship-joint.parquet",
    "--workers", "2", "--plot", JOINT_FIGURE,
]  # fmt: skip


def save_tutorial_controller(folder: Path) -> None:
    """``my_controller.py`` as the tutorial has the reader save it (step 6)."""
    page = (DOCS / "tutorial.md").read_text(encoding="utf-8")
    (block,) = re.findall(r"^```python\n(# my_controller\.py\n.*?)^```", page, re.M | re.S)
    (folder / "my_controller.py").write_text(block, encoding="utf-8")


def main(argv: list[str]) -> int:
    joint = "--joint" in argv
    argv = [a for a in argv if a != "--joint"]
    command, figure = (JOINT_COMMAND, JOINT_FIGURE) if joint else (COMMAND, FIGURE)
    work = Path(argv[0] if argv else "sensitivity-work").resolve()
    work.mkdir(parents=True, exist_ok=True)
    save_tutorial_controller(work)
    os.chdir(work)  # the controller spec is relative, as in the page's command
    report = io.StringIO()
    with contextlib.redirect_stdout(report):
        status = puckboard(command)
    (work / ("report-joint.txt" if joint else "report.txt")).write_text(
        report.getvalue(), encoding="utf-8"
    )
    print(report.getvalue())
    if status != 0:
        return status
    shutil.copyfile(work / figure, DOCS / "img" / figure)
    print(f"wrote docs/img/{figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
