"""A folder of controller modules, for grading a class on the same episodes.

Convention: every ``*.py`` file directly in the folder (names starting with ``_`` or
``.`` are skipped) is one entry and must define a factory named
:data:`FACTORY_NAME`, ``make_controller(**params)``, returning a
:class:`~puckboard.behaviours.Controller` or a list of layers — the same contract as any
``path/file.py:factory`` controller spec. The file's name identifies the entry in the
results (``alice.py`` → ``submissions/alice.py:make_controller``).

Files are only listed here, not imported: a submission that fails to import or build is
scored as ``error`` episodes instead of stopping the sweep.
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["FACTORY_NAME", "controllers_in_dir"]

#: The factory each controller module in a ``--controllers-dir`` must define.
FACTORY_NAME = "make_controller"


def controllers_in_dir(directory: str | os.PathLike[str]) -> list[str]:
    """Controller specs for the modules in ``directory``, sorted by file name."""
    folder = Path(directory)
    if not folder.is_dir():
        raise ValueError(f"--controllers-dir {str(folder)!r} is not a folder")
    files = sorted(
        p for p in folder.glob("*.py") if p.is_file() and not p.name.startswith(("_", "."))
    )
    if not files:
        raise ValueError(
            f"--controllers-dir {str(folder)!r} holds no controller modules (*.py files "
            f"defining {FACTORY_NAME}(**params))"
        )
    return [f"{p.as_posix()}:{FACTORY_NAME}" for p in files]
