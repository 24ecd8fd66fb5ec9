"""What runs in a submission's own process: its pre-flight check, and its replays.

Both are *unit tasks* of the sweep's workers (:mod:`puckboard.sweep.host`): each reports
its units, so the parent stops one that runs past its wall-clock limit by killing the
process, and a unit whose process was stopped or died (``lost``) comes back as a result
that says so. Nothing here runs in the grading process: a submission's import, its
factory and its first ticks run beside nothing but the submission itself.

The pre-flight check (:func:`preflight`) is the same for ``puckboard challenge check``
and for grading, so a file the check passes is never refused at grading. It refuses
only what no episode could survive — a file that is not Python, does not import, has
no factory, whose factory raises or returns something that is not a controller — and
times the controller's ticks against the control period on the first practice cell.
"""

from __future__ import annotations

import logging
import math
import re
import statistics
import time
import traceback
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..sweep.worker import LostUnit, quieter_logs, report_unit_began, report_unit_done

if TYPE_CHECKING:
    from ..scenario.scene import Scene

__all__ = ["LOST_VERDICTS", "TIMED_TICKS", "preflight", "replay"]

log = logging.getLogger(__name__)

#: Ticks the pre-flight check times (two seconds of a 50 ms loop).
TIMED_TICKS = 40
#: A lost pre-flight unit's verdict, by how it was lost.
LOST_VERDICTS = {"timeout": "timeout", "exited": "exited", "crashed": "crashed"}


def preflight(
    spec: str,
    factory: str,
    scene: Scene,
    parameters: Mapping[str, Any],
    seed: int,
    ticks: int = TIMED_TICKS,
    *,
    start: int = 0,
    lost: LostUnit | None = None,
) -> list[dict[str, Any]]:
    """The pre-flight check of the file of ``spec`` (``path.py:factory``): one unit,
    whose value is a dict — ``verdict`` (``ok`` or why not), ``message``, ``details``
    (what Python shows for the student's error), ``layers``, and ``ticks`` (the timing
    of ``ticks`` control ticks on ``scene`` with ``parameters`` and ``seed``) — and
    ``spec``, to tell the results of several files apart."""
    if lost is not None:
        value = {**_lost_check(lost), "spec": spec}
    else:
        report_unit_began(0)
        with quieter_logs():
            value = {**_check(spec, factory, scene, parameters, seed, ticks), "spec": spec}
    report_unit_done(0, value)
    return [value]


def _lost_check(lost: LostUnit) -> dict[str, Any]:
    verdict = LOST_VERDICTS.get(lost.kind, "crashed")
    limit = re.search(r"limit of ([\d.]+ s)", lost.message)
    within = f"within {limit.group(1)}" if limit else "in time"
    what = {
        "timeout": f"did not finish its pre-flight check {within}: importing it, building its "
        "controller or its first ticks sleep, block or never return",
        "exited": f"ended its process during its pre-flight check: {lost.message}",
    }.get(lost.kind, f"its pre-flight check was lost: {lost.message}")
    return {"verdict": verdict, "message": what, "details": "", "layers": [], "ticks": None}


def _check(
    spec: str,
    factory: str,
    scene: Scene,
    parameters: Mapping[str, Any],
    seed: int,
    ticks: int,
) -> dict[str, Any]:
    from ..behaviours.presets import load_controller, resolve_factory
    from ..usercode import user_traceback

    path = Path(spec.rpartition(":")[0])
    out: dict[str, Any] = {
        "verdict": "ok",
        "message": "",
        "details": "",
        "layers": [],
        "ticks": None,
    }

    def refuse(verdict: str, message: str, exc: BaseException | None = None) -> dict[str, Any]:
        out["verdict"], out["message"] = verdict, message
        if exc is not None:
            text = user_traceback(exc, load_controller, resolve_factory)
            out["details"] = text or "".join(traceback.format_exception_only(type(exc), exc))
        return out

    try:
        compile(path.read_bytes(), path.name, "exec")
    except (SyntaxError, ValueError) as exc:
        out["details"] = "".join(traceback.format_exception_only(type(exc), exc))
        return refuse("not-python", f"{path.name} is not valid Python: {_first(exc)}")
    try:
        resolve_factory(spec)
    except SystemExit as exc:
        return refuse(
            "exited", f"importing {path.name} ended the process (sys.exit({exc.code!r}))", exc
        )
    except MemoryError as exc:
        return refuse("memory", f"importing {path.name} ran out of memory", exc)
    except ValueError as exc:
        if f"has no callable {factory!r}" in str(exc):
            return refuse("no-factory", f"{path.name} defines no {factory}(**params)")
        return refuse("import-failed", f"importing {path.name} raised {_first(exc)}", exc)
    except Exception as exc:
        return refuse(
            "import-failed",
            f"importing {path.name} raised {type(exc).__name__}: {_first(exc)}",
            exc,
        )
    try:
        controller = load_controller(spec)
    except SystemExit as exc:
        return refuse("exited", f"{factory}() ended the process (sys.exit({exc.code!r}))", exc)
    except MemoryError as exc:
        return refuse("memory", f"{factory}() ran out of memory", exc)
    except TypeError as exc:
        if "must return a Controller" in str(exc):
            return refuse("wrong-return", f"{factory}() {_returned(exc)}")
        return refuse("factory-failed", f"{factory}() raised TypeError: {_first(exc)}", exc)
    except Exception as exc:
        return refuse(
            "factory-failed", f"{factory}() raised {type(exc).__name__}: {_first(exc)}", exc
        )
    out["layers"] = [layer.name for layer in controller.every_layer]
    out["ticks"] = _time_ticks(spec, scene, parameters, seed, ticks)
    return out


def _first(exc: BaseException) -> str:
    lines = str(exc).strip().splitlines()
    return lines[0] if lines else type(exc).__name__


def _returned(exc: BaseException) -> str:
    said = re.search(r"returned (\w+)", str(exc))
    what = said.group(1) if said else "something else"
    return f"returned {what}; it must return a Controller or a list of layers"


def _time_ticks(
    spec: str, scene: Scene, parameters: Mapping[str, Any], seed: int, ticks: int
) -> dict[str, Any]:
    """Run ``ticks`` control cycles of an episode and time each robot's controller tick
    and each layer (what its own code spends); an exception is reported, not raised."""
    from ..control.episode import Episode

    overrides = {k: v for k, v in parameters.items() if not k.startswith("label.")}
    overrides.pop("duration", None)
    tick_s: list[float] = []
    layers: dict[str, float] = {}
    out: dict[str, Any] = {"period_s": None, "ticks": 0}
    try:
        episode = Episode(scene, controller=spec, seed=seed, overrides=overrides or None)
        period = float(episode.loop.period)
        out["period_s"] = period
        for controller in episode.controllers.values():
            controller.time_layers(layers)
            tick = controller.tick

            def timed(ns: Any, tick: Any = tick) -> Any:
                t0 = time.perf_counter()
                try:
                    return tick(ns)
                finally:
                    tick_s.append(time.perf_counter() - t0)

            controller.tick = timed  # type: ignore[method-assign]
        episode.run(min(ticks * period, episode.scene.duration), stop_early=False)
    except Exception as exc:  # the layer's own error: the check reports it, grading counts it
        from ..usercode import own_traceback

        out["error"] = f"{type(exc).__name__}: {_first(exc)}"
        out["details"] = own_traceback(exc)
    robots = max(1, len(scene.robots))
    count = len(tick_s) // robots
    out["ticks"] = count
    if tick_s:
        out["median_s"] = statistics.median(tick_s)
        out["p95_s"] = sorted(tick_s)[max(0, math.ceil(0.95 * len(tick_s)) - 1)]
        out["max_s"] = max(tick_s)
    if layers and count:
        name, spent = max(layers.items(), key=lambda item: item[1])
        out["slowest_layer"] = name
        out["slowest_layer_s"] = spent / (count * robots)
    return out


def replay(
    scene: Scene,
    spec: str,
    seed: int,
    parameters: Mapping[str, Any],
    title: str,
    description: str,
    tag: str,
    *,
    start: int = 0,
    lost: LostUnit | None = None,
) -> list[dict[str, Any]]:
    """One episode run again with a recorder (one unit): ``{"tag": tag, "data": the replay
    page's document}``, ``data`` ``None`` when the run raised or was lost. The document's
    title and scene description are ``title`` and ``description``, not the run's own,
    which may name its seed."""
    with quieter_logs():
        data = None if lost is not None else _recorded(scene, spec, seed, parameters)
    if data is not None:
        data["title"] = title
        data["scene"]["description"] = description
    value = {"tag": tag, "data": data}
    report_unit_done(0, value)
    return [value]


def _recorded(
    scene: Scene, spec: str, seed: int, parameters: Mapping[str, Any]
) -> dict[str, Any] | None:
    from ..control.episode import Episode
    from ..recording.recorder import Recorder
    from ..web.replay import replay_data

    report_unit_began(0)
    overrides = {k: v for k, v in parameters.items() if not k.startswith("label.")}
    duration = overrides.pop("duration", None)
    try:
        episode = Episode(scene, controller=spec, seed=seed, overrides=overrides or None)
        recorder = Recorder.for_episode(episode).attach(episode)
        episode.run(duration)
        return replay_data(recorder.recording())
    except Exception:  # its layers' own error: no replay, its row says why
        log.debug("replay of %s failed", spec, exc_info=True)
        return None
