"""The benchmark registry: every suite by name, run, or skipped with the reason.

``puckboard bench`` runs the suites in :data:`SUITES`, one module each (:mod:`.core`,
:mod:`.sim`, :mod:`.coppeliasim`, :mod:`.estimation` ...), all timed by :mod:`.timing`
and shown by :mod:`.report`. A suite is a function
``run_suite(steps: int | None) -> dict`` named as ``"module:function"`` so that other
parts of puckboard (or a user's package) can add their own; a suite whose module, or an
optional package it needs, is not installed is skipped with a note naming the extra to
install, not an error.

Every figure is the median over several repeats after a warm-up, timed with
``time.perf_counter``; results carry the number of repeats and the machine so they can be
compared honestly. Benchmarks are never pass/fail tests.
"""

from __future__ import annotations

import inspect
import logging
import os
import pkgutil
import platform
from collections.abc import Callable, Mapping
from typing import Any

from .._extras import extra_for, missing_package_message

__all__ = ["DEFAULT_SUITES", "SUITES", "machine", "resolve_suite", "run_suites", "suite_options"]

log = logging.getLogger(__name__)

#: Suite name → ``"module:function"``; the function takes ``steps`` (or None for its
#: default) and returns a dict of results.
SUITES: dict[str, str] = {
    "core": "puckboard.bench.core:run_suite",
    "floor": "puckboard.bench.floor:run_suite",
    "sim": "puckboard.bench.sim:run_suite",
    "coppeliasim": "puckboard.bench.coppeliasim:run_suite",
    "sweep": "puckboard.bench.sweep:run_suite",
    "estimation": "puckboard.bench.estimation.suite:run_suite",
    "emulator": "puckboard.bench.emulator:run_suite",
    "scale": "puckboard.bench.scale:run_suite",
    "web": "puckboard.bench.web:run_suite",
    "compare": "puckboard.bench.compare:run_suite",
    "sensitivity": "puckboard.bench.sensitivity:run_suite",
    "transfer": "puckboard.bench.transfer:run_suite",
    "challenge": "puckboard.bench.challenge:run_suite",
}

#: Suites run when none is named.
DEFAULT_SUITES: tuple[str, ...] = ("core", "sim")


def machine() -> dict[str, Any]:
    """What the figures were measured on."""
    import numpy as np

    return {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "platform": platform.platform(terse=True),
        "processor": platform.processor() or platform.machine(),
        "cpus": os.cpu_count(),
    }


def resolve_suite(name: str) -> Callable[..., dict[str, Any]]:
    """The function behind suite ``name``; ImportError if its module is missing."""
    try:
        target = SUITES[name]
    except KeyError:
        raise KeyError(f"unknown benchmark suite {name!r}; suites: {', '.join(SUITES)}") from None
    return pkgutil.resolve_name(target)  # type: ignore[no-any-return]


def suite_options(name: str) -> set[str]:
    """The keyword options suite ``name`` accepts beyond ``steps`` (empty if not importable)."""
    try:
        return _keywords(resolve_suite(name))
    except (ImportError, AttributeError):
        return set()


def _keywords(fn: Callable[..., Any]) -> set[str]:
    """The keyword options a suite function takes beyond ``steps``."""
    params = inspect.signature(fn).parameters.values()
    return {p.name for p in params if p.name != "steps" and p.kind is not p.VAR_KEYWORD}


def run_suites(
    names: list[str], steps: int | None = None, options: Mapping[str, Any] | None = None
) -> dict[str, Any]:
    """Run the named suites; a suite whose module is absent gets ``{"skipped": reason}``.

    So does a suite that needs one of puckboard's optional packages (the coppeliasim
    suite imports pyzmq only when it starts its server): the reason names the extra
    that installs it. Any other ImportError is a bug and propagates.

    ``options`` are keyword arguments for the suites (e.g. ``seeds`` for ``estimation``);
    each suite receives those it accepts, so one command line can serve several suites.
    """
    results: dict[str, Any] = {"machine": machine(), "suites": {}}
    for name in names:
        try:
            fn = resolve_suite(name)
        except ImportError as exc:
            results["suites"][name] = {"skipped": _missing(name, exc)}
            continue
        except AttributeError as exc:
            results["suites"][name] = {"skipped": f"suite function not available ({exc})"}
            continue
        accepted = _keywords(fn)
        kwargs = {k: v for k, v in (options or {}).items() if k in accepted}
        try:
            results["suites"][name] = fn(steps, **kwargs)
        except ImportError as exc:
            if extra_for(exc) is None:
                raise
            results["suites"][name] = {"skipped": _missing(name, exc)}
        if "skipped" in results["suites"][name]:
            log.info("benchmark suite %r skipped: %s", name, results["suites"][name]["skipped"])
    return results


def _missing(name: str, exc: ImportError) -> str:
    """Why suite ``name`` cannot run: the extra to install when the missing module is one
    of puckboard's optional packages, else Python's own words (a user's suite)."""
    if extra_for(exc) is not None:
        return missing_package_message(f"suite {name!r}", exc)
    return f"module not available ({exc})"
