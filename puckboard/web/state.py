"""What the web page shows, as plain JSON-ready data, from a local run or a served world.

The page draws three things, each sent as it changes:

* the **scene**, once: arena, line, obstacles, dummies, and per robot its name, colour
  and IR sensor poses (so the page can draw the readings as rays from the right places);
* a **frame**, up to :data:`FRAME_RATE` times a second: simulation time, real-time
  factor, per robot its pose, IR distances, wheel command, layer in control (with the
  layer's colour) and who drives it, the judge's events so far and, at the end, its
  verdict; in a served world whose scene a client's ``sim.stopSimulation`` has just
  restored, the events and verdict of the run that ended, marked ``previous`` (see
  :class:`ServerFollower`);
* a robot's **details** when someone opens its panel: its blackboard keys with values and
  ages (what ``puckboard monitor`` shows), or, for a served world whose controllers run in
  other processes, the served sensor values; its arbitration timeline so far; and its
  behaviour tree with every node's status at the last tick (a
  :class:`~puckboard.behaviours.tracing.TreeTrace`; a served world shows the tree its
  client publishes as the string signal ``<model>.tree``).

:class:`EpisodeFollower` builds them from a :class:`~puckboard.control.episode.Episode`
(``puckboard run --web``) reading only the blackboard and the scene, like every other
visual tool; :class:`ServerFollower` from the
:class:`~puckboard.backends.coppeliasim.server.view.ServedView` of a
:class:`~puckboard.backends.coppeliasim.server.socket_loop.RemoteApiServer`
(``puckboard serve --web``: the server's typed read-only face, never its internals),
where the layer in control is what each client publishes as the string signal
``<model>.layer``. Both only read: the simulation is the same with or without a page
watching it.

Colours and event words come from :mod:`puckboard.viz.style`, as in the other figures.
"""

from __future__ import annotations

import json
import math
import time
from collections import deque
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..behaviours.tracing import TreeTrace, trace
from ..profile import get_profile
from ..records import PROX_NAMES
from ..viz.scene_art import scene_bounds
from ..viz.style import event_label, hex_colour, layer_colour, layer_colours, robot_colours

if TYPE_CHECKING:
    from ..backends.coppeliasim.server.view import ServedStep, ServedView
    from ..control.episode import Episode
    from ..scenario.judge import Judge
    from ..scenario.scene import Scene

__all__ = ["FRAME_RATE", "EpisodeFollower", "ServerFollower", "describe_scene", "page_nodes"]

#: Frames a second sent to the page (the simulation may step far faster).
FRAME_RATE = 20.0
#: Details (blackboard tables) a second: heavier, and read by one panel at a time.
DETAIL_RATE = 4.0
#: Trail points kept per robot (one each time it moved 5 mm).
TRAIL_POINTS = 4000
_TRAIL_STEP = 0.005

Publish = Callable[[str, Any], None]


def _r(value: float, digits: int = 4) -> float:
    return round(float(value), digits)


def page_nodes(
    nodes: Sequence[dict[str, Any]], colours: dict[str, str] | None = None
) -> list[dict[str, Any]]:
    """A tree's nodes as the page draws them: each layer with its colour (``colours``,
    else the layer's colour everywhere else)."""
    out = []
    for node in nodes:
        keep = ("name", "type", "kind", "parent", "depth", "memory")
        entry: dict[str, Any] = {k: node[k] for k in keep if k in node}
        if entry.get("kind") == "layer":
            name = str(entry.get("name"))
            entry["colour"] = (colours or {}).get(name) or layer_colour(name)
        out.append(entry)
    return out


#: What the panel says when a served robot's client publishes no tree.
NO_REMOTE_TREE = (
    "the program driving this robot does not publish its behaviour tree "
    "('puckboard run --backend coppeliasim' does)"
)


def describe_scene(scene: Scene, *, driver: str) -> dict[str, Any]:
    """The static part of the picture (JSON-ready); ``driver`` says what runs it."""
    from ..scenario.scene import CircleObstacle

    names = [r.name for r in scene.robots]
    colours = robot_colours(names, {r.name: r.colour for r in scene.robots})
    robots = []
    for spec in scene.robots:
        profile = get_profile(spec.profile)
        robots.append({
            "name": spec.name,
            "colour": colours[spec.name],
            "profile": profile.name,
            "radius": profile.body_radius,
            "sensors": [[_r(p.x), _r(p.y), _r(p.heading)] for p in profile.prox_poses],
            "sensor_names": list(PROX_NAMES),
            "range": profile.prox_range,
        })  # fmt: skip
    obstacles: list[dict[str, Any]] = []
    for ob in scene.obstacles:
        if isinstance(ob, CircleObstacle):
            obstacles.append({"name": ob.name, "circle": [ob.x, ob.y, ob.radius],
                              "colour": hex_colour(ob.colour)})  # fmt: skip
        else:
            obstacles.append({"name": ob.name, "polygon": ob.vertices.round(4).tolist(),
                              "colour": hex_colour(ob.colour)})  # fmt: skip
    out: dict[str, Any] = {
        "name": scene.name,
        "description": scene.description,
        "driver": driver,
        "dt": scene.dt,
        "duration": scene.duration,
        "floor": hex_colour(scene.floor_colour),
        "robots": robots,
        "obstacles": obstacles,
        "dummies": [{"name": d.name, "x": d.x, "y": d.y} for d in scene.dummies],
        "arena": None,
        "track": None,
    }
    if scene.arena is not None:
        a = scene.arena
        out["arena"] = {"xmin": a.xmin, "ymin": a.ymin, "xmax": a.xmax, "ymax": a.ymax,
                        "colour": hex_colour(a.colour)}  # fmt: skip
    if scene.track is not None:
        t = scene.track
        out["track"] = {"points": t.points.round(4).tolist(), "width": t.width,
                        "closed": t.closed, "colour": hex_colour(t.colour)}  # fmt: skip
    xmin, xmax, ymin, ymax = scene_bounds(scene, margin=0.0)  # as the other figures frame it
    out["bounds"] = [xmin, ymin, xmax, ymax]
    return out


class _Follower:
    """What both followers share: throttling, trails, layer timelines, real-time factor."""

    def __init__(self, scene: Scene, publish: Publish, *, driver: str) -> None:
        self.scene = scene
        self.publish = publish
        self.names = [r.name for r in scene.robots]
        self.scene_json = describe_scene(scene, driver=driver)
        self.trails: list[deque[tuple[float, float]]] = [
            deque(maxlen=TRAIL_POINTS) for _ in self.names
        ]
        #: per robot, the layer changes so far: [time (s), layer]
        self.timelines: list[list[tuple[float, str]]] = [[] for _ in self.names]
        #: The colour of each layer of this run's controllers, where they are known (a
        #: local run's): the colours of the run's plots and recordings.
        self.layer_colours: dict[str, str] = {}
        self._next_frame = 0.0
        self._next_detail = 0.0
        self._rtf_window: deque[tuple[float, float]] = deque(maxlen=int(2 * FRAME_RATE))
        self.frames = 0
        #: the simulation time of the newest step seen (s)
        self.t = 0.0
        #: which run the trails and timelines are of: a page that sees another number
        #: starts new trails (counts the served world's restores)
        self.run = 0
        #: the run that ended, while the page shows it as such (:class:`ServerFollower`)
        self.previous: PreviousRun | None = None
        publish("scene", self.scene_json)

    def _track(self, t: float, poses: np.ndarray, layers: Sequence[str | None]) -> None:
        """Every step: layer changes (for complete timelines) and trail points."""
        self.t = t
        for i, layer in enumerate(layers):
            if layer is None:
                continue
            line = self.timelines[i]
            if not line or line[-1][1] != layer:
                line.append((round(t, 3), layer))
        for i, trail in enumerate(self.trails):
            x, y = float(poses[i, 0]), float(poses[i, 1])
            if not trail or math.hypot(x - trail[-1][0], y - trail[-1][1]) >= _TRAIL_STEP:
                trail.append((round(x, 4), round(y, 4)))

    def _due(self, now: float, *, force: bool = False) -> bool:
        if not force and now < self._next_frame:
            return False
        self._next_frame = now + 1.0 / FRAME_RATE
        return True

    def _rtf(self, t: float, now: float) -> float | None:
        window = self._rtf_window
        if window and t < window[-1][0]:
            window.clear()  # the simulation was restarted
        window.append((t, now))
        (t0, w0), (t1, w1) = window[0], window[-1]
        return round((t1 - t0) / (w1 - w0), 2) if w1 - w0 > 0.2 else None

    def _frame(
        self, t: float, now: float, robots: list[dict[str, Any]], judge: Judge | None,
        status: str,
    ) -> dict[str, Any]:  # fmt: skip
        """A frame; ``judge``'s events and verdict, which are the previous run's while
        :attr:`previous` is set (then ``previous`` says when that run ended)."""
        self.frames += 1
        frame: dict[str, Any] = {
            "t": round(t, 3),
            "rtf": self._rtf(t, now),
            "status": status,
            "robots": robots,
            "events": [],
            "verdict": None,
            "run": self.run,
            "previous": None if self.previous is None else self.previous.header(),
        }
        if judge is not None:
            frame["events"] = [
                {"t": round(e.time_s, 2), "robot": e.robot, "kind": e.kind,
                 "text": event_label(e.kind)}
                for e in sorted(judge.events, key=lambda e: e.time_s)
            ]  # fmt: skip
            if judge.decided:
                frame["verdict"] = {
                    "success": bool(judge.success),
                    "failure": judge.failure,
                    "robot": judge.failure_robot,
                    "text": "success" if judge.success else event_label(judge.failure or ""),
                }
        return frame

    def trails_json(self) -> dict[str, Any]:
        """Every robot's trail so far (``trails``) and which run it is of (``run``: a page
        that then gets a frame of another run starts new trails); ``previous``: the
        previous run's number, end time and trails, while it is shown."""
        prev = self.previous
        return {
            "run": self.run,
            "trails": {name: list(trail) for name, trail in zip(self.names, self.trails)},
            "previous": None if prev is None else {
                **prev.header(), "trails": dict(zip(self.names, prev.trails)),
            },
        }  # fmt: skip

    def timeline(self, i: int) -> list[dict[str, Any]]:
        """Robot ``i``'s layer changes: this run's, or the previous run's while it is
        shown (the details then say when it ended: ``end``)."""
        line = self.timelines[i] if self.previous is None else self.previous.timelines[i]
        return [{"t": t, "layer": layer, "colour": self.colour_of(layer)}
                for t, layer in list(line)]  # fmt: skip

    def colour_of(self, layer: str | None) -> str:
        """``layer``'s colour in this run (its own colour where the controllers are not
        known)."""
        return (self.layer_colours.get(layer) if layer else None) or layer_colour(layer)


class PreviousRun:
    """A served world's run that ``sim.stopSimulation`` ended: what the page keeps
    showing, labelled as the previous run, until the next run steps."""

    __slots__ = ("judge", "run", "t", "timelines", "trails")

    def __init__(
        self, run: int, t: float, judge: Judge, trails: list[list[tuple[float, float]]],
        timelines: list[list[tuple[float, str]]],
    ) -> None:  # fmt: skip
        self.run = run
        self.t = round(t, 3)
        self.judge = judge
        self.trails = trails
        self.timelines = timelines

    def header(self) -> dict[str, Any]:
        """Which run it was and when it ended (s)."""
        return {"run": self.run, "t": self.t}


def _robot_entry(
    name: str, pose: Sequence[float], prox: Sequence[float] | None, wheels: Sequence[float] | None,
    layer: str | None, driver: str, colour: str | None = None,
) -> dict[str, Any]:  # fmt: skip
    return {
        "name": name,
        "pose": [_r(pose[0]), _r(pose[1]), _r(pose[2])],
        "prox": None if prox is None else [_r(d) for d in prox],
        "wheels": None if wheels is None else [_r(w, 3) for w in wheels],
        "layer": layer,
        "layer_colour": colour or layer_colour(layer),
        "driver": driver,
    }


class EpisodeFollower(_Follower):
    """Follows a local run; register it with ``episode.add_observer`` (and as a close
    observer, for the final frame)."""

    def __init__(self, episode: Episode, publish: Publish) -> None:
        super().__init__(episode.scene, publish, driver="puckboard run")
        self.episode = episode
        self.adapters = [episode.connection.adapters[n] for n in self.names]
        self.finished = False
        self._order: list[int] | None = None
        controllers = getattr(episode, "controllers", None) or {}
        self.traces: list[TreeTrace | None] = [
            trace(controllers[n]) if n in controllers else None for n in self.names
        ]
        self.layer_colours = layer_colours(
            [
                layer.name
                for n in self.names
                if n in controllers
                for layer in controllers[n].every_layer
            ]
        )
        self._nodes = [
            None if t is None else page_nodes(t.nodes, self.layer_colours) for t in self.traces
        ]
        self._ticks = [0 if t is None else t.ticks for t in self.traces]
        self._ticked = [False] * len(self.names)

    def _layers(self) -> list[str | None]:
        """The layer each controller chose this cycle (one record read per robot: this
        runs every cycle, for complete timelines)."""
        out: list[str | None] = []
        for a in self.adapters:
            try:
                out.append(a.ns.get("command/layer").value)
            except KeyError:  # no cycle yet
                out.append(None)
        return out

    def _poses(self) -> np.ndarray:
        ep = self.episode
        if ep.world is not None:
            if self._order is None:
                self._order = [ep.world.index(n) for n in self.names]
            return np.asarray(ep.world.poses)[self._order]
        out = np.zeros((len(self.names), 3))
        for i, a in enumerate(self.adapters):
            try:
                pose = a.ns.get("pose").value
            except KeyError:
                continue
            out[i] = (pose.x, pose.y, pose.theta)
        return out

    def __call__(self, episode: Episode | None = None) -> None:
        for i, tr in enumerate(self.traces):  # every cycle: was the tree ticked in this one?
            if tr is not None:
                self._ticked[i] = tr.ticks != self._ticks[i]
                self._ticks[i] = tr.ticks
        self.update(force=False)

    def close(self, episode: Episode | None = None) -> None:
        self.finished = True
        self.update(force=True)

    def update(self, *, force: bool) -> None:
        ep = self.episode
        layers = self._layers()
        poses = self._poses()
        t = float(ep.time)
        self._track(t, poses, layers)
        now = time.monotonic()
        if not self._due(now, force=force):
            return
        snaps = [a.ns.snapshot() for a in self.adapters]
        robots = []
        for i, name in enumerate(self.names):
            prox = snaps[i].value("proximity")
            cmd = snaps[i].value("command/wheels")
            robots.append(_robot_entry(
                name, poses[i].tolist(), None if prox is None else prox.distance.tolist(),
                None if cmd is None else (cmd.left, cmd.right), layers[i], "puckboard run",
                self.colour_of(layers[i]),
            ))  # fmt: skip
        status = "finished" if self.finished else "running"
        self.publish("frame", self._frame(t, now, robots, ep.judge, status))
        if force or now >= self._next_detail:
            self._next_detail = now + 1.0 / DETAIL_RATE
            details = {
                n: self._detail(i, snaps[i], layers[i], round(t, 3))
                for i, n in enumerate(self.names)
            }
            self.publish("details", details)

    def _tree(self, i: int, active: str | None, t: float) -> dict[str, Any]:
        tr, nodes = self.traces[i], self._nodes[i]
        if tr is None or nodes is None:
            return {"note": "this robot has no controller of puckboard's to show", "t": t}
        status = tr.status.tolist() if self._ticked[i] else [0] * len(nodes)
        note = None if self._ticked[i] else "the tree was not ticked: its inputs were stale"
        return {"nodes": nodes, "status": status, "active": active, "note": note, "t": t}

    def _detail(self, i: int, snap: Any, active: str | None, t: float) -> dict[str, Any]:
        from ..records import Sensor
        from ..viz.monitor import format_value

        # a sensor the robot does not read (a camera that is off) is "off", shown plain:
        # in red, as a sensor that should report and does not, it sent users looking
        # for a fault
        enabled = self.adapters[i].enabled_sensors
        off = {s.key for s in Sensor if s not in enabled}
        keys = []
        for key in sorted(snap):
            rec = snap.record(key)
            if rec is None:
                status = "off" if key in off else "missing"
                keys.append({"key": key, "value": status if key in off else "—", "age": None,
                             "status": status})  # fmt: skip
                continue
            keys.append({
                "key": key, "value": format_value(rec.value), "age": round(snap.now - rec.stamp, 3),
                "status": snap.status(key),
            })  # fmt: skip
        return {"keys": keys, "timeline": self.timeline(i), "source": "blackboard",
                "tree": self._tree(i, active, t)}  # fmt: skip


class ServerFollower(_Follower):
    """Follows a served world through its view (``server.view()``); register it with
    ``server.add_step_observer``. The judge
    of the scene watches the served world too (restarted when a client restarts it).

    A client's ``sim.stopSimulation`` restores the scene the moment its run ends: the
    robots jump back to their start. The view then shows the restored scene as it is
    (a new trail from each robot's start, the time back at 0) *and* the run that ended,
    labelled as the previous run: its verdict, events, timelines and (faded) trails stay
    until the next run steps. Clearing them instead would take the verdict off the
    projector a fraction of a second after it was reached, before the class has read it;
    leaving them unlabelled would say the robots at their start had just succeeded.
    """

    def __init__(self, served: ServedView, publish: Publish) -> None:
        super().__init__(served.scene, publish, driver="puckboard serve")
        self.served = served
        self._step = served.step()  # the last one looked at
        self.judge = self._new_judge()
        self._model_names = list(served.model_names)
        self._trees: dict[str, tuple[Any, dict[str, Any] | None]] = {}  # signal → parsed

    def _new_judge(self) -> Judge:
        from ..scenario.judge import Judge

        return Judge(self.scene)

    def _restored(self, step: ServedStep) -> None:
        """The served world was replaced (``sim.stopSimulation`` restored the scene): the
        run that ended becomes the previous run, and a new one begins (not yet stepped)."""
        if self.judge.started:
            self.judge.finish()  # the run is over: its outcome, as the client's judge has it
        if self.judge.started or any(len(trail) > 1 for trail in self.trails):
            self.previous = PreviousRun(
                self.run, self.t, self.judge, [list(t) for t in self.trails], self.timelines
            )
        self.run += 1
        self.judge = self._new_judge()
        for trail in self.trails:
            trail.clear()
        self.timelines = [[] for _ in self.names]
        self.t = step.time

    def __call__(self, _server: object = None) -> None:
        """One look at the served world (the server calls it with itself: the view is
        all this reads)."""
        served = self.served
        step = served.step()
        if step.run != self._step.run:
            self._restored(step)
        self._step = step
        if self.previous is not None and step.step_count > 0:
            self.previous = None  # the next run has begun: only its own trails and events
        poses = step.poses
        layers = [served.signal(f"{m}.layer") for m in self._model_names]
        if served.running and step.step_count > 0:
            self.judge.update(step.time, poses, step.collisions)
        self._track(step.time, poses, layers)
        now = time.monotonic()
        if not self._due(now):
            return
        drivers = self._drivers(now)
        targets = served.targets
        robots = [
            _robot_entry(name, poses[i].tolist(), step.prox_distance[i].tolist(),
                         targets[i].tolist(), layers[i], drivers[i])
            for i, name in enumerate(self.names)
        ]  # fmt: skip
        running = served.running
        status = "paused" if running and served.paused else "running" if running else "stopped"
        if self.previous is not None:
            judge: Judge | None = self.previous.judge
        else:
            judge = self.judge if self.judge.started else None
        frame = self._frame(step.time, now, robots, judge, status)
        if status != "running":
            frame["rtf"] = None  # standing still: no rate to speak of
        self.publish("frame", frame)
        if now >= self._next_detail:
            self._next_detail = now + 1.0 / DETAIL_RATE
            t = round(step.time, 3)
            self.publish("details", {
                n: {**self._detail(i), "tree": self._tree(i, layers[i], t)}
                for i, n in enumerate(self.names)
            })  # fmt: skip

    def _tree(self, i: int, active: str | None, t: float) -> dict[str, Any]:
        """The tree the robot's client publishes (``<model>.tree``: JSON with ``nodes``
        and ``status``, one digit per node), read and checked once per change."""
        raw = self.served.signal(f"{self._model_names[i]}.tree")
        cached = self._trees.get(self._model_names[i])
        if cached is None or cached[0] != raw:
            cached = (raw, _parse_tree(raw))
            self._trees[self._model_names[i]] = cached
        tree = cached[1]
        if tree is None:
            return {"note": NO_REMOTE_TREE, "t": t}
        return {**tree, "active": active, "note": None, "t": t}

    def _drivers(self, now: float) -> list[str]:
        out = ["no client"] * len(self.names)
        for client in self.served.clients():
            silent = now - client.last_seen
            mode = "stepping" if client.stepping else "free-running"
            state = "idle" if silent > 2.0 and not client.waiting else mode
            for robot in sorted(client.robots):
                out[robot] = f"client {client.short} · {state}"
        return out

    def _detail(self, i: int) -> dict[str, Any]:
        step = self._step
        prox = ", ".join(
            f"{n} {100 * d:.1f}" for n, d in zip(PROX_NAMES, step.prox_distance[i].tolist())
            if d < step.prox_range[i]
        )  # fmt: skip
        ground = "L {:.2f}  C {:.2f}  R {:.2f}".format(*step.ground[i].tolist())
        left, right = step.wheel_speeds[i].tolist()
        x, y, th = step.poses[i].tolist()
        keys = [
            {"key": "proximity", "value": f"{prox} cm" if prox else "nothing in range",
             "age": 0.0, "status": "fresh"},
            {"key": "ground", "value": ground, "age": 0.0, "status": "fresh"},
            {"key": "wheel_speeds", "value": f"L {left:+.2f}  R {right:+.2f} rad/s",
             "age": 0.0, "status": "fresh"},
            {"key": "pose", "value": f"x {x:+.3f} m  y {y:+.3f} m  θ {math.degrees(th):+6.1f}°",
             "age": 0.0, "status": "fresh"},
        ]  # fmt: skip
        out: dict[str, Any] = {
            "keys": keys, "timeline": self.timeline(i), "source": "served sensors",
        }  # fmt: skip
        if self.previous is not None:  # the previous run's timeline, to the time it ended
            out["end"] = self.previous.t
        return out


def _parse_tree(raw: Any) -> dict[str, Any] | None:
    """A client's ``<model>.tree`` signal, or ``None`` when absent or malformed (a client
    is not trusted: only names, kinds, parents and status digits are kept)."""
    text = _text(raw)
    if not text:
        return None
    try:
        data = json.loads(text)
        nodes = [
            {"name": str(n["name"])[:80], "type": str(n.get("type", ""))[:40],
             "kind": str(n.get("kind", "behaviour"))[:12], "parent": int(n["parent"]),
             "depth": int(n.get("depth", 0))}
            for n in data["nodes"][:64]
        ]  # fmt: skip
        status = [int(c) for c in str(data["status"])[: len(nodes)]]
    except (ValueError, TypeError, KeyError, AttributeError):
        return None
    return {"nodes": page_nodes(nodes), "status": status + [0] * (len(nodes) - len(status))}


def _text(value: Any) -> str | None:
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return value if isinstance(value, str) else None
