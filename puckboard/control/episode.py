"""An episode: one scene, one controller per robot, one backend, judged from start to end.

This is what ``puckboard run`` does, as a library call::

    from puckboard.control.episode import run_episode
    result = run_episode("two-robot-pass", controller="stock", seed=3)
    print(result.success, result.failure)        # False parallel_driving
    print(result.to_dict())                      # the `puckboard run --json` object

An :class:`Episode` opens the backend (``open_backend(backend, scene, seed=...)``), builds
one fresh controller per robot from the scene's ``RobotSpec.controller`` (or the
``controller`` given), binds them in a :class:`~puckboard.control.loop.ControlLoop` and
feeds a :class:`~puckboard.scenario.judge.Judge` after every cycle: from the embedded world's
ground truth (poses and the simulator's collision counts) when there is one, else from
each robot's ``pose`` blackboard key. Viewers and recorders hook in with
:meth:`Episode.add_observer` and :meth:`Episode.add_close_observer`; they only read, so a
run is the same with or without them.

``overrides`` change a scene or the controllers without editing files, by dotted name
(``noise.proximity``, ``dt``, ``layer.<LayerName>.<attribute>``, ``profile.<path>``, ...;
the dialect and every name are in :mod:`puckboard.scenario.overrides`): the scene's are
applied before the backend opens, the layers' (:mod:`puckboard.behaviours.overrides`) on
each robot's controller, and ``controller.<keyword>`` is handed to every robot's
controller factory (``controller.speed`` builds ``improved(speed=...)``); ``variation`` =
``plausible`` (also the ``variation`` argument) builds each robot from numbers drawn
within its profile's plausible ranges.
"""

from __future__ import annotations

import dataclasses
import difflib
import inspect
import json
import logging
import math
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..backends.registry import abilities_of, default_backend, open_backend, resolve_backend
from ..behaviours.controller import Controller
from ..behaviours.overrides import apply_layer_overrides, factory_keywords
from ..behaviours.presets import ControllerFactory, load_controller
from ..behaviours.tracing import TreeTrace, trace
from ..errors import SceneError
from ..profile import RobotProfile, get_profile
from ..scenario.judge import Judge
from ..scenario.preparation import RunRequest, prepare_scene
from ..scenario.result import EpisodeResult
from ..scenario.scene import RobotSpec, Scene
from ..scenario.settings import CONTROL_LATENCY, CONTROL_REPEATED, check_scene
from ..scenario.variation import NONE
from .loop import ControlLoop

if TYPE_CHECKING:
    from ..backends.base import RobotAdapter
    from ..sim.world import World

__all__ = ["MAX_STEPS", "Episode", "check_steps", "run_episode"]

log = logging.getLogger(__name__)

#: The most steps one episode may take. ``dt=1e-9`` over a one-second run is 10⁹ steps,
#: days of computing that look like a hang and end only when killed; the bound turns
#: such a typo into an error before anything runs. Ten million steps are a 5.8-day run
#: at the usual dt of 0.05 s. Raise it (``puckboard.control.episode.MAX_STEPS = ...``)
#: for a run that really needs more.
MAX_STEPS = 10_000_000

EpisodeObserver = Callable[["Episode"], None]


def check_steps(duration: float, dt: float) -> int:
    """The steps of ``dt`` seconds in ``duration`` seconds; a ``ValueError`` that names
    the limit, the two numbers and the way out when they exceed :data:`MAX_STEPS`."""
    steps = math.ceil(duration / dt - 1e-9)
    if steps > MAX_STEPS:
        raise ValueError(
            f"{duration:g} s in steps of dt={dt:g} s would take {steps:,} steps, more than "
            f"one episode may take ({MAX_STEPS:,}, puckboard.control.episode.MAX_STEPS); "
            "use a larger dt or a shorter duration, or raise MAX_STEPS"
        )
    return steps


def _resolve_scene(scene: Scene | str | Path) -> Scene:
    if isinstance(scene, Scene):
        return scene
    from ..scenario.scenefile import load_scene

    return load_scene(scene)


def _robot_controller(
    spec: str | ControllerFactory,
    robot: str,
    scene: Scene,
    keywords: Mapping[str, Any],
    *,
    from_scene: bool,
) -> Controller:
    """Robot ``robot``'s controller, its factory handed ``keywords``; a bad spec the scene
    gave names the scene's file and the robot, since the spec is not on the command line
    that ran it."""
    if not from_scene:
        return load_controller(spec, **keywords)
    try:
        return load_controller(spec, **keywords)
    except ValueError as exc:
        where = scene.source or f"scene {scene.name!r}"
        raise SceneError(f"{where}: robot {robot!r}: {exc}") from exc


class Episode:
    """One judged run; see the module docstring. Use it once: build, observe, :meth:`run`."""

    def __init__(
        self,
        scene: Scene | str | Path,
        *,
        controller: str | ControllerFactory | None = None,
        seed: int = 0,
        backend: str | None = None,
        overrides: Mapping[str, Any] | None = None,
        variation: str = "none",
        **backend_options: Any,
    ) -> None:
        self.backend = backend if backend is not None else default_backend()
        _check_call(seed, self.backend, backend_options)
        overrides = dict(overrides or {})
        variation = _one_variation(variation, overrides.pop("variation", None))
        self.seed = int(seed)
        # the scene this run plays: the scene as given through named steps, each condition
        # drawn once (scenario.preparation); then what the backend drives (below)
        able = abilities_of(self.backend)
        run = RunRequest(
            self.seed, overrides, variation, simulates_link=able.link_timing,
            drives_robot=not able.simulated,
        )  # fmt: skip
        prepared = prepare_scene(_resolve_scene(scene), run)
        self.scene = prepared.scene
        try:
            check_scene(self.scene)  # every setting in bounds, however the scene was built
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        #: what the variation drew besides the robots, as the result reports it (None when
        #: nothing: every variation but reality-gap)
        self.conditions = (
            None if prepared.conditions is None else prepared.conditions.to_dict()
        )
        specs = {
            r.name: (controller if controller is not None else r.controller)
            for r in self.scene.robots
        }
        # build the controllers first: a bad spec must fail before a backend is opened
        keywords = factory_keywords(overrides)
        self.controllers: dict[str, Controller] = {
            name: _robot_controller(spec, name, self.scene, keywords, from_scene=controller is None)
            for name, spec in specs.items()
        }
        apply_layer_overrides(self.controllers, overrides)
        self.controller_label = _label(specs)
        self.connection = open_backend(self.backend, self.scene, seed=self.seed, **backend_options)
        try:
            self.world = self.connection.world
            self.blackboard = self.connection.blackboard
            specs = self._keep_the_robots_driven(specs)
            self.scene = _driven_profiles(self.scene, self.connection.adapters)
            bindings = [(self.connection.adapters[n], self.controllers[n]) for n in specs]
            self.loop = ControlLoop(bindings, period=_loop_period(self.scene, self.world))
            self.judge = Judge(self.scene)
            self._clock_offset: float | None = None  # record clock minus run clock, real robots
            self._order = [self.world.index(n) for n in specs] if self.world is not None else None
            # the judge takes the robots in the scene's order: the world's rows, reordered
            # only when they differ
            self._reorder = self._order is not None and self._order != list(range(len(specs)))
        except BaseException:
            self.connection.close()
            raise
        self.observers: list[EpisodeObserver] = []
        self.close_observers: list[EpisodeObserver] = []
        self.result_observers: list[EpisodeObserver] = []
        self.result: EpisodeResult | None = None
        self.wall_s = 0.0
        self.loop.add_observer(self._after_cycle)
        self.loop.add_close_observer(self._on_close)
        for name, ctrl in self.controllers.items():
            show = getattr(self.connection.adapters[name], "show_tree", None)
            if show is not None:  # a served world's page can draw this robot's tree
                _show_tree(trace(ctrl), show)
        if self.world is not None:
            self._feed_judge()  # the start poses (after any start jitter)

    def _keep_the_robots_driven(
        self, specs: dict[str, str | ControllerFactory]
    ) -> dict[str, str | ControllerFactory]:
        """``specs`` of the robots the opened backend drives: a real robot (or a remote
        simulator holding fewer robots) drives only the robots it has, and the episode,
        and the judge, shrink to those; a simulator missing one is an error."""
        adapters = self.connection.adapters
        missing = [n for n in specs if n not in adapters]
        if not missing:
            return specs
        if self.world is not None or not adapters:
            raise SceneError(
                f"backend {self.backend!r} has no robot called {', '.join(missing)}; it has "
                f"{', '.join(adapters)}"
            )
        log.warning(
            "backend %r drives only %s; leaving out %s",
            self.backend, ", ".join(adapters), ", ".join(missing),
        )  # fmt: skip
        kept = tuple(r for r in self.scene.robots if r.name in adapters)
        self.scene = dataclasses.replace(self.scene, robots=kept)
        specs = {n: specs[n] for n in specs if n in adapters}
        self.controllers = {n: self.controllers[n] for n in specs}
        return specs

    # -- observation -----------------------------------------------------------------------
    @property
    def time(self) -> float:
        return self.loop.time

    def add_observer(self, observer: EpisodeObserver) -> None:
        """``observer(episode)`` after every control cycle (after the judge has seen it)."""
        self.observers.append(observer)

    def add_close_observer(self, observer: EpisodeObserver) -> None:
        """``observer(episode)`` once when the run ends, however it ends."""
        self.close_observers.append(observer)

    def add_result_observer(self, observer: EpisodeObserver) -> None:
        """``observer(episode)`` once the run completed and the judge's verdict is final
        (:attr:`result` is set); not called when the run ends on an error or Ctrl-C."""
        self.result_observers.append(observer)

    def _feed_judge(self) -> None:
        if self.world is not None:
            poses = self.world.poses
            collisions = self.world.collisions
            if self._reorder:
                poses = poses[self._order]
                collisions = collisions[self._order]
            self.judge.update(self.world.time, poses, collisions)
            return
        poses = np.empty((len(self.controllers), 3))
        stamp = self.loop.time
        for k, name in enumerate(self.controllers):
            record = self.connection.adapters[name].ns.snapshot(["pose"]).get("pose")
            if record is None:
                return  # this backend gives no pose (yet): nothing to judge on this cycle
            pose = record.value
            poses[k] = (pose.x, pose.y, pose.theta)
            stamp = record.stamp  # the pose describes the sensing instant, not the step after
        if not self.loop.synchronous:
            # a real robot's records carry the host's clock (seconds since it booted): the
            # judge, and the events it reports, count from the start of the run instead
            if self._clock_offset is None:
                self._clock_offset = stamp - self.loop.time
            stamp -= self._clock_offset
        self.judge.update(stamp, poses)

    def _after_cycle(self, loop: ControlLoop) -> None:
        self._feed_judge()
        for obs in self.observers:
            obs(self)

    def _on_close(self, loop: ControlLoop) -> None:
        for obs in self.close_observers:
            try:
                obs(self)
            except Exception:
                log.exception("episode close observer %r failed", obs)

    def _note_idle_controllers(self) -> None:
        for name, controller in self.controllers.items():
            note = _idle_note(name, controller)
            if note is not None:
                log.warning("%s", note)

    # -- running ---------------------------------------------------------------------------
    def check_duration(self, duration: float | None = None) -> float:
        """``duration`` (default: the scene's) if this episode can run that long: a finite
        positive number of seconds, at least one control cycle (a shorter one would run
        that whole cycle all the same, unsaid) and within :data:`MAX_STEPS` steps, else
        ``ValueError``.

        :meth:`run` checks it too; calling it first lets a caller refuse a bad run
        before it opens windows or promises files. The step is the simulation's (the
        control period on a real robot), since that is what the run will count.
        """
        duration = self.scene.duration if duration is None else float(duration)
        if not (math.isfinite(duration) and duration > 0):
            raise ValueError(
                f"duration must be a finite positive number of seconds, got {duration:g}"
            )
        cycle = self.loop.period
        if duration < cycle * (1 - 1e-9):
            what = "simulation step" if self.loop.synchronous else "control cycle"
            raise ValueError(
                f"duration {duration:g} s is shorter than one {what} of {cycle:g} s, the "
                f"shortest run there is; give at least {cycle:g} s"
            )
        check_steps(duration, self.loop.period / max(1, self.loop.steps_per_cycle))
        return duration

    def run(self, duration: float | None = None, *, stop_early: bool = True) -> EpisodeResult:
        """Run for ``duration`` s of simulation (default: the scene's), stopping as soon as
        the judge's verdict is final when ``stop_early``. Everything is closed at the end,
        on error and on Ctrl-C. A duration :meth:`check_duration` refuses raises
        ``ValueError`` before anything runs (the backend stays open for another try)."""
        if self.result is not None:
            raise RuntimeError("an Episode runs once; build a new one for another run")
        duration = self.check_duration(duration)
        until = (lambda loop: self.judge.decided) if stop_early else None
        t0 = time.perf_counter()
        try:
            self.loop.run(duration, until=until)
        finally:
            self.wall_s = time.perf_counter() - t0
            self.connection.close()
        self.judge.finish()
        self._note_idle_controllers()
        steps = (
            self.world.step_count
            if self.world is not None
            else self.loop.cycles * max(1, self.loop.steps_per_cycle)
        )
        self.result = EpisodeResult(
            scenario=self.scene.name,
            controller=self.controller_label,
            seed=self.seed,
            dt_s=self.scene.dt,
            steps=int(steps),
            sim_time_s=float(self.loop.time),
            wall_s=self.wall_s,
            success=bool(self.judge.success),
            failure=self.judge.failure,
            failures=list(self.judge.failures),
            robots=self.judge.metrics(),
            events=sorted(self.judge.events, key=lambda e: e.time_s),
            conditions=self.conditions,
        )
        if not self.scene.control.is_default(self.scene.dt):
            self.result.control_period_s = float(self.loop.period)
            self.result.control_latency_s = float(self.scene.control.latency)
            if self.scene.control.varies:
                self.result.control_cycle = _cycle_summary(self.scene)
        for obs in self.result_observers:
            try:
                obs(self)
            except Exception:
                log.exception("episode result observer %r failed", obs)
        return self.result


def _cycle_summary(scene: Scene) -> dict[str, float]:
    """How the scene's loop varies cycle by cycle, as the result reports it (s, share)."""
    control = scene.control
    out: dict[str, float] = {}
    if control.cycle_latency is not None:
        for name in ("median", "p90", "max"):
            out[f"latency_{name}_s"] = round(
                control.latency + control.cycle_latency.quantile(name), 6
            )
    out["repeated"] = round(control.repeated, 6)
    return out


def _loop_period(scene: Scene, world: World | None) -> float | None:
    """The control period the scene asks for (None: the loop's default, one step or a real
    robot's 0.05 s). A latency is simulated by the embedded world, which delays each
    wheel command itself; on any other backend the delay is the link's own, so a scene
    asking for one there is refused rather than silently run without it (a drawn or a
    measured one already was, naming where it came from: scenario.preparation)."""
    control = scene.control
    if world is None and control.needs_link:
        name, value = (
            (CONTROL_LATENCY.name, f"{control.latency:g} s")
            if control.latency > 0 or control.cycle_latency is not None
            else (CONTROL_REPEATED.name, f"{control.repeated:g}")
        )
        raise SceneError(
            f"{name} = {value} is simulated by the embedded backend only; a real link "
            f"brings its own (measure it with puckboard calibrate link), so leave {name} "
            "at 0 on this backend"
        )
    return control.period


def _one_variation(argument: str, setting: Any) -> str:
    """The variation of a run given ``variation=`` and perhaps an overrides' ``variation``
    too: two different ones are refused (which was meant, only the caller knows)."""
    if setting is None:
        return str(argument)
    if str(argument) not in (NONE.name, str(setting)):
        raise ValueError(
            f"variation given twice: {argument!r} and, in the overrides, {setting!r}; give it once"
        )
    return str(setting)


#: The keywords of :func:`run_episode` itself; the rest go to the backend.
_OWN_KEYWORDS = (
    "controller", "seed", "duration", "overrides", "backend", "stop_early", "variation"
)  # fmt: skip


def _check_call(seed: Any, backend: str, options: Mapping[str, Any]) -> None:
    """Refuse, in the caller's words, a seed numpy would refuse with its own and a
    misspelt keyword (``seeed=3``), which would otherwise travel on to the backend and
    come back as "World.__init__() got an unexpected keyword argument"."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a whole number ≥ 0, got {seed!r}")
    if not options:
        return
    try:
        params = inspect.signature(resolve_backend(backend)).parameters.values()
    except (ImportError, TypeError, ValueError):
        return  # the backend itself is the problem: opening it says so
    named = [p.name for p in params if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)]
    open_ended = any(p.kind is p.VAR_KEYWORD for p in params)
    for key in options:
        meant = difflib.get_close_matches(key, [*_OWN_KEYWORDS, *named], n=1)
        if key in named or (open_ended and not (meant and meant[0] in _OWN_KEYWORDS)):
            continue  # the backend's own option (or one it hands on and checks itself)
        guess = f" (did you mean {meant[0]}=?)" if meant else ""
        raise TypeError(
            f"unexpected keyword {key}={options[key]!r}{guess}; run_episode takes "
            f"{', '.join(_OWN_KEYWORDS)} and the {backend} backend's options"
        )


def _idle_note(robot: str, controller: Controller) -> str | None:
    """What to say of a controller none of whose layers ever applied (the robot stood
    still all run, and the judge can only call it stuck), else ``None``."""
    if controller.asked_ticks == 0 or controller.driven_ticks:
        return None
    names = ", ".join(layer.name for layer in controller.every_layer)
    return (
        f"robot {robot!r}: no layer of controller {controller.name!r} applied in any of its "
        f"{controller.asked_ticks} ticks, so the robot stood still; check what applies() "
        f"returns in {names} (a bottom layer that always applies, such as Cruise, keeps it "
        "moving)"
    )


def _driven_profiles(scene: Scene, adapters: Mapping[str, RobotAdapter]) -> Scene:
    """``scene`` with every robot given the profile of the robot actually driven.

    A simulator builds its robots from the scene, but a real robot (or the emulator
    that stands in for one) is what it is: the e-puck2 adapter drives the ``epuck``
    profile whatever the scene says. The judge measures with the profile's body, and
    the results name it, so both must be the driven robot's.
    """
    robots = tuple(
        _driven(r, adapters[r.name].profile) if r.name in adapters else r for r in scene.robots
    )
    if all(a is b for a, b in zip(robots, scene.robots)):
        return scene
    return dataclasses.replace(scene, robots=robots)


def _driven(robot: RobotSpec, driven: RobotProfile) -> RobotSpec:
    """``robot`` as driven: unchanged when its adapter drives the profile the scene
    believes (overrides included); else the adapter's profile, and no drawn truth (what
    a real robot truly is, nobody drew)."""
    if get_profile(robot.profile) == driven:
        return robot
    return dataclasses.replace(robot, profile=driven, actual=None)


def _show_tree(tr: TreeTrace, show: Callable[[str], None]) -> None:
    """After every tick, hand ``show`` the tree and its statuses as JSON (composed only
    when a status changed: in a Selector that is when another layer takes over)."""
    nodes = [{k: n[k] for k in ("name", "type", "kind", "parent", "depth")} for n in tr.nodes]
    last = [""]

    def listener(trace: TreeTrace) -> None:
        codes = trace.codes()
        if codes != last[0]:
            last[0] = codes
            show(json.dumps({"nodes": nodes, "status": codes}, separators=(",", ":")))

    tr.listeners.append(listener)


def _label(specs: Mapping[str, str | ControllerFactory]) -> str:
    names = []
    for spec in specs.values():
        text = spec if isinstance(spec, str) else getattr(spec, "__name__", repr(spec))
        if text not in names:
            names.append(text)
    return ",".join(names)


def run_episode(
    scene: Scene | str | Path,
    *,
    controller: str | ControllerFactory | None = None,
    seed: int = 0,
    duration: float | None = None,
    overrides: Mapping[str, Any] | None = None,
    backend: str | None = None,
    stop_early: bool = True,
    variation: str = "none",
    **backend_options: Any,
) -> EpisodeResult:
    """Build an :class:`Episode` and run it; see the module docstring."""
    episode = Episode(
        scene, controller=controller, seed=seed, backend=backend, overrides=overrides,
        variation=variation, **backend_options,
    )  # fmt: skip
    return episode.run(duration, stop_early=stop_early)
