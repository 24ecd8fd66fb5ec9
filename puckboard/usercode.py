"""Errors in a user's own code, shown the way Python shows them, without puckboard's frames.

A student who runs ``puckboard run --controller my_layer.py:make`` with a typo in
``my_layer.py`` needs what ``python my_layer.py`` would print: the file, the line, the
caret and the message. Python's traceback would add a dozen frames of puckboard's loader
and of importlib, which say nothing to the student and hide the one frame that matters.

:func:`own_traceback` does the same for an error raised while the code runs (a layer's
``command`` called by the loop, the arbiter and py_trees): it keeps the frames outside
puckboard and py_trees, which are the user's.

:func:`user_traceback` keeps the frames *below* a loader function (the code it ran on the
user's behalf) and drops importlib's and runpy's plumbing from them, as Python does for
its own ``python file.py``. The loader is named by the functions that run user code
(:func:`puckboard.behaviours.presets.resolve_factory`, :func:`runpy.run_module`'s
``_run_code``), so an error raised *by* the loader itself (its own one-line messages)
or anywhere else (a backend) is not mistaken for the user's.
"""

from __future__ import annotations

import traceback
from collections.abc import Callable
from pathlib import Path, PurePath
from typing import Any

__all__ = ["own_traceback", "user_traceback"]

#: Modules whose frames are plumbing between a loader and the code it runs.
_PLUMBING = ("importlib", "runpy", "pkgutil")


def user_traceback(exc: BaseException, *loaders: Callable[..., Any]) -> str | None:
    """What Python shows for ``exc`` if it was raised by code one of ``loaders`` ran
    (an imported file, a factory it called), else ``None``.

    The text is Python's own: ``Traceback (most recent call last):`` and the frames from
    the user's code down to where it raised (calls from there into puckboard included),
    then the exception; for a :class:`SyntaxError` in the file itself only the file,
    line, caret and message, as Python prints it for a script.
    """
    codes = {(fn.__code__.co_filename, fn.__code__.co_name) for fn in _functions(loaders)}
    frames = traceback.extract_tb(exc.__traceback__)
    last = max((i for i, f in enumerate(frames) if (f.filename, f.name) in codes), default=None)
    if last is None:
        return None
    below = [f for f in frames[last + 1 :] if not _plumbing(f.filename)]
    if not below and not isinstance(exc, SyntaxError):
        return None  # the loader raised it itself: its message is one of ours
    lines: list[str] = []
    if below:
        lines.append("Traceback (most recent call last):\n")
        lines += traceback.format_list(below)
    lines += traceback.format_exception_only(type(exc), exc)
    return "".join(lines)


def _functions(loaders: tuple[Callable[..., Any], ...]) -> list[Any]:
    """The plain functions behind ``loaders`` (a method's function, a wrapper's target)."""
    out = []
    for fn in loaders:
        fn = getattr(fn, "__func__", fn)
        fn = getattr(fn, "__wrapped__", fn)
        if hasattr(fn, "__code__"):
            out.append(fn)
    return out


def _plumbing(filename: str) -> bool:
    """A frame of importlib (frozen or not), runpy or pkgutil."""
    if filename.startswith("<frozen "):
        return True
    path = PurePath(filename)
    return path.stem in _PLUMBING or any(part in _PLUMBING for part in path.parts[-3:-1])


def own_traceback(exc: BaseException) -> str:
    """The traceback of ``exc`` without the frames inside puckboard and py_trees.

    What is left is the controller author's own code, where the fix goes; a student
    need not read the loop, the arbiter and py_trees' tick to find their line. When no
    frame is left (the error is puckboard's own), the whole traceback is kept.
    """
    import py_trees

    package = Path(__file__).resolve().parent
    hidden = (package, Path(py_trees.__file__).resolve().parent)
    shown = package / "examples"  # installed teaching examples are code to read

    def own(frame: traceback.FrameSummary) -> bool:
        path = Path(frame.filename).resolve()
        return path.is_relative_to(shown) or not any(path.is_relative_to(h) for h in hidden)

    frames = traceback.extract_tb(exc.__traceback__)
    kept = [f for f in frames if own(f)]
    if not kept:
        return "".join(traceback.format_exception(exc))
    return "".join(
        [
            "Traceback (most recent call last):\n",
            *traceback.format_list(kept),
            *traceback.format_exception_only(exc),
        ]
    )
