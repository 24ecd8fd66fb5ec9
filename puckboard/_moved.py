"""Old import paths kept working for one release after a module moved.

A module that moved leaves a two-line stub at its old path that calls
:func:`alias_module`: the first import warns with a :class:`DeprecationWarning` that names
the new path, then the old name *is* the new module (``sys.modules`` points both names at
one object), so ``isinstance`` checks and monkeypatching behave the same under both.
"""

from __future__ import annotations

import importlib
import sys
import warnings
from pathlib import Path
from types import ModuleType

__all__ = ["alias_module", "warn_moved"]

#: The release that removes the old paths.
REMOVED_IN = "0.3"


def warn_moved(old: str, new: str) -> None:
    """Warn, at the user's import or attribute access, that ``old`` is now ``new``."""
    warnings.warn(
        f"{old} moved to {new}; the old name is removed in puckboard {REMOVED_IN}. "
        f"Import {new} instead.",
        DeprecationWarning,
        stacklevel=_user_stacklevel(),
    )


def alias_module(old: str, new: str) -> ModuleType:
    """Make module ``old`` an alias of ``new`` (call it from the stub at ``old``'s path)."""
    warn_moved(old, new)
    module = importlib.import_module(new)
    sys.modules[old] = module
    return module


_PACKAGE_DIR = str(Path(__file__).resolve().parent)


def _user_stacklevel() -> int:
    """Stack level (for :func:`warnings.warn` in :func:`warn_moved`) of the user's frame.

    Frames of puckboard itself and of the import system are skipped, so the warning points
    at the line that imported the old name.
    """
    frame = sys._getframe(1)  # warn_moved: level 1
    level = 1
    while frame.f_back is not None and _is_internal(frame.f_code.co_filename):
        frame = frame.f_back
        # warnings.warn itself does not count the import system's frames
        if not _is_import_system(frame.f_code.co_filename):
            level += 1
    return level


def _is_import_system(filename: str) -> bool:
    return filename.startswith("<frozen importlib")


def _is_internal(filename: str) -> bool:
    return _is_import_system(filename) or filename.startswith(_PACKAGE_DIR)
