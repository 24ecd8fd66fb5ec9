"""Recorded runs: what each robot sensed, decided and did, cycle by cycle, on disk.

A recording is the one source every after-the-fact view reads: animations are rendered
from it (never from the screen, so a file is identical with or without a window), plots
are drawn from it, and it can be shared with a class or attached to a bug report. It is
backend-neutral: the :class:`Recorder` reads only blackboard keys every backend writes
(``pose``, ``proximity``, ``ground``, ``command/wheels``, ``command/layer``), so a run in
the embedded simulator, in CoppeliaSim or on a real e-puck records the same way. A
value a backend does not provide (a real robot has no ground-truth ``pose``) is NaN.

On disk a recording is one compressed NumPy archive (``.npz``, read with
:func:`numpy.load`, no pickles), format version :data:`FORMAT_VERSION`:

============  =============  =======  ==============================================
array         shape          dtype    meaning
============  =============  =======  ==============================================
``time``      T              float64  time of each cycle's sensing (s)
``pose``      T×N×3          float64  x (m), y (m), theta (rad); NaN when unknown
``wheels``    T×N×2          float64  commanded left, right wheel speed (rad/s)
``layer``     T×N            int16    index into ``layer_names`` (-1: not known)
``proximity`` T×N×8          float32  IR distances (m), ps0..ps7; ``range`` = nothing
``ground``    T×N×3          float32  ground values 0 (black) .. 1 (white), gs0..gs2
``meta``      scalar string  unicode  JSON: see below
============  =============  =======  ==============================================

and, from format 3, what each robot's arbiter decided every tick: the status of every
node of its behaviour tree and the blackboard values its layers read, with their ages
(``tree``, ``read_age``, ``read_status``, ``read_<j>``; see
:mod:`puckboard.recording.decisions`). Format 2 recordings, which lack them, still load.

T is the number of recorded cycles, N the number of robots (in ``meta["robots"]``
order). ``meta`` holds ``format`` (``"puckboard-recording"``), ``version``,
``robots``, ``layer_names`` (the table ``layer`` indexes), ``robot_layers`` (each
robot's layers in priority order, for timelines), ``colours`` (RGB per robot),
``scenario``, ``controller``, ``seed``, ``backend``, ``dt``, ``created`` (UTC, ISO
8601), ``puckboard`` (version), ``scene`` (the scene in the scene file's JSON form, see
:func:`~puckboard.scenario.conversion.scene_to_dict`, so ``puckboard run`` can load it
again; or ``null``) and, when the run was judged, ``events`` (``time_s``, ``robot``,
``kind``: collisions, passes, lost line, ...) and ``prox_range`` (m, the distance
that means "nothing seen").

The recorder writes into preallocated arrays that double when full, so recording a
long run costs a few array stores per cycle and no per-cycle objects of its own.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import logging
import math
import os
import zipfile
import zlib
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import numpy.typing as npt

from .._version import __version__
from .atomic import create_beside
from .decisions import DecisionRecorder, Decisions

if TYPE_CHECKING:
    from ..behaviours.controller import Controller
    from ..blackboard import Blackboard
    from ..scenario.scene import Scene

__all__ = [
    "FORMAT_VERSION",
    "Recorder",
    "Recording",
    "RobotSeries",
    "load_recording",
]

log = logging.getLogger(__name__)

FORMAT_NAME = "puckboard-recording"
#: 2: ``meta["scene"]`` is the scene file's own JSON form (scenario.conversion).
#: 3: the arbiter's decisions (tree statuses, the values the layers read); optional.
FORMAT_VERSION = 3
#: The oldest format :func:`load_recording` reads (format 1 predates the first release).
OLDEST_FORMAT_VERSION = 2
"""Bumped whenever the on-disk layout changes incompatibly."""

RECORDED_KEYS: tuple[str, ...] = ("pose", "proximity", "ground", "command/wheels", "command/layer")
"""Blackboard keys (relative to each robot's namespace) a :class:`Recorder` reads."""

_PROX_RANGE_DEFAULT = 0.05


class RecordedRobots(Protocol):
    """What a recorder reads of a run's connection: the names of the robots it drives."""

    @property
    def adapters(self) -> Mapping[str, object]: ...


class RecordedRun(Protocol):
    """What a recorder needs of a run: a :class:`~puckboard.control.episode.Episode`, or
    anything with its blackboard, connection and observers. A recording is backend-neutral
    and records any run, so it names what it reads instead of importing the loop or a
    backend; :meth:`Recorder.for_episode` reads the rest, the controllers, scene, loop,
    seed, backend and judge, where the run has them."""

    @property
    def blackboard(self) -> Blackboard: ...

    @property
    def connection(self) -> RecordedRobots: ...

    # Any: the observer is handed the run itself, whatever class it is
    def add_observer(self, observer: Callable[[Any], None]) -> None: ...

    def add_close_observer(self, observer: Callable[[Any], Any]) -> None: ...


#: The recorded arrays, by name, in the order a file stores them: their type and, for
#: the per-robot ones, each robot's row shape (the array is T×N×shape; ``None``: T only).
#: Every place that handles the arrays goes through this table.
_ARRAYS: dict[str, tuple[type[np.generic], tuple[int, ...] | None]] = {
    "time": (np.float64, None),
    "pose": (np.float64, (3,)),
    "wheels": (np.float64, (2,)),
    "layer": (np.int16, ()),
    "proximity": (np.float32, (8,)),
    "ground": (np.float32, (3,)),
}


@dataclasses.dataclass(frozen=True)
class RobotSeries:
    """One robot's time series: read-only views into a :class:`Recording`'s arrays."""

    name: str
    time: npt.NDArray[np.float64]
    pose: npt.NDArray[np.float64]  # T×3
    wheels: npt.NDArray[np.float64]  # T×2
    layer_index: npt.NDArray[np.int16]  # T
    proximity: npt.NDArray[np.float32]  # T×8
    ground: npt.NDArray[np.float32]  # T×3
    layers: tuple[str, ...]  # priority order, highest first
    layer_names: tuple[str, ...]  # the recording's layer table
    colour: tuple[int, int, int]

    def layer_at(self, i: int) -> str | None:
        """Name of the layer in control at cycle ``i`` (``None`` if not recorded)."""
        k = int(self.layer_index[i])
        return self.layer_names[k] if k >= 0 else None


class Recording:
    """A loaded or finished recording; see the module docstring for the arrays."""

    def __init__(
        self,
        *,
        time: npt.ArrayLike,
        pose: npt.ArrayLike,
        wheels: npt.ArrayLike,
        layer: npt.ArrayLike,
        proximity: npt.ArrayLike,
        ground: npt.ArrayLike,
        meta: Mapping[str, Any],
        decisions: Decisions | None = None,
    ) -> None:
        self.time = np.asarray(time, dtype=np.float64)
        self.pose = np.asarray(pose, dtype=np.float64)
        self.wheels = np.asarray(wheels, dtype=np.float64)
        self.layer = np.asarray(layer, dtype=np.int16)
        self.proximity = np.asarray(proximity, dtype=np.float32)
        self.ground = np.asarray(ground, dtype=np.float32)
        self.meta: dict[str, Any] = dict(meta)
        self.robot_names: tuple[str, ...] = tuple(self.meta.get("robots", ()))
        self.layer_names: tuple[str, ...] = tuple(self.meta.get("layer_names", ()))
        t, n = len(self.time), len(self.robot_names)
        for name, arr in self.arrays().items():
            tail = _ARRAYS[name][1]
            if tail is not None and arr.shape != (t, n, *tail):
                raise ValueError(
                    f"recording array {name!r} has shape {arr.shape}, expected {(t, n, *tail)} "
                    f"for {t} cycles of {n} robots"
                )
        #: what each robot's arbiter decided every tick; ``None`` when not recorded
        self.decisions = decisions
        if decisions is not None:
            decisions.check(t, n)
        self._scene: Scene | None = None
        self._scene_read = False  # meta["scene"] is read once, when first asked for

    # -- convenient access -----------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.time)

    def arrays(self) -> dict[str, np.ndarray]:
        """The recorded arrays by name (the recording's own, not copies)."""
        return {name: getattr(self, name) for name in _ARRAYS}

    @property
    def duration(self) -> float:
        """Recorded time span (s)."""
        return float(self.time[-1] - self.time[0]) if len(self.time) > 1 else 0.0

    def robot(self, name: str | int) -> RobotSeries:
        """The series of one robot, by name or index."""
        if isinstance(name, int):
            i = name
        else:
            try:
                i = self.robot_names.index(name)
            except ValueError:
                raise KeyError(
                    f"recording has no robot {name!r}; robots: {', '.join(self.robot_names)}"
                ) from None
        rname = self.robot_names[i]
        colours = self.meta.get("colours") or {}
        layers = (self.meta.get("robot_layers") or {}).get(rname) or self.layer_names
        return RobotSeries(
            name=rname,
            time=self.time,
            pose=self.pose[:, i],
            wheels=self.wheels[:, i],
            layer_index=self.layer[:, i],
            proximity=self.proximity[:, i],
            ground=self.ground[:, i],
            layers=tuple(layers),
            layer_names=self.layer_names,
            colour=tuple(colours.get(rname, (60, 160, 60))),  # type: ignore[arg-type]
        )

    def robots(self) -> list[RobotSeries]:
        return [self.robot(i) for i in range(len(self.robot_names))]

    def tree_at(self, robot: str | int, tick: int) -> dict[str, str]:
        """Node name → status name (``"RUNNING"``, ``"not ticked"``, …) of ``robot``'s
        tree after control tick ``tick``; empty when the recording has no decisions."""
        name = self.robot(robot).name
        if self.decisions is None:
            return {}
        return self.decisions.node_status(name, self.robot_names.index(name), tick)

    @property
    def scene(self) -> Scene | None:
        """The recorded :class:`~puckboard.scenario.scene.Scene` (``None`` if none was recorded)."""
        if not self._scene_read:
            data = self.meta.get("scene")
            self._scene = None if data is None else scene_from_json(data)
            self._scene_read = True
        return self._scene

    @property
    def title(self) -> str:
        """``scenario · controller · seed N`` for figure titles."""
        parts = [str(self.meta.get("scenario") or "run")]
        if self.meta.get("controller"):
            parts.append(str(self.meta["controller"]))
        if self.meta.get("seed") is not None:
            parts.append(f"seed {self.meta['seed']}")
        return " · ".join(parts)

    # -- disk ------------------------------------------------------------------------------
    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the recording as a compressed ``.npz`` (atomically: a reader never sees
        half a file). Returns the path written."""
        path = Path(path)
        if path.suffix.lower() != ".npz":
            raise ValueError(f"recordings are saved as .npz files, got {str(path)!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        meta = dict(self.meta)
        meta.update(format=FORMAT_NAME, version=FORMAT_VERSION)
        extra: dict[str, np.ndarray] = {}
        if self.decisions is not None:
            extra, decided = self.decisions.to_arrays(
                {"proximity": self.proximity, "ground": self.ground}
            )
            meta.update(decided)
        # the file's members in this order: the arrays, the metadata, the decisions
        members: dict[str, Any] = {
            **self.arrays(),
            "meta": np.array(json.dumps(meta, default=_json_default)),
            **extra,
        }
        fd, tmp = create_beside(path)
        try:
            with os.fdopen(fd, "wb") as fh:
                np.savez_compressed(fh, **members)
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        return path

    def __repr__(self) -> str:
        return (
            f"<Recording {self.title!r}: {len(self)} cycles, {self.duration:.2f} s, "
            f"robots {', '.join(self.robot_names)}>"
        )


def load_recording(path: str | os.PathLike[str]) -> Recording:
    """Read a recording written by :meth:`Recording.save` (or a :class:`Recorder`)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no recording at {str(path)!r}")
    not_a_recording = (
        f"{str(path)!r} is not a puckboard recording (a .npz file written by "
        "'puckboard run --record run.npz')"
    )
    try:
        loaded = np.load(path, allow_pickle=False)
    except OSError as exc:
        if exc.errno is not None:  # the file exists but cannot be read (permissions)
            raise ValueError(f"cannot read {str(path)!r}: {exc.strerror}") from exc
        log.debug("numpy cannot load %s: %s", path, exc)
        raise ValueError(not_a_recording) from exc
    except (ValueError, EOFError, zipfile.BadZipFile) as exc:
        # numpy's reasons are about its own formats ("load it unsafely using the
        # allow_pickle= keyword"): advice a user must not follow for a file of unknown
        # origin, so it goes to the debug log, not into the message
        log.debug("numpy cannot load %s: %s", path, exc)
        raise ValueError(not_a_recording) from exc
    if not isinstance(loaded, np.lib.npyio.NpzFile):
        raise ValueError(f"{not_a_recording}; it holds a single NumPy array")
    try:
        with loaded as data:
            arrays = {k: data[k] for k in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        log.debug("numpy cannot read the arrays of %s: %s", path, exc)
        raise ValueError(f"{not_a_recording}, or a damaged one") from exc
    if "meta" not in arrays:
        raise ValueError(f"{str(path)!r} is an .npz file but not a puckboard recording")
    meta = json.loads(str(arrays.pop("meta")))
    if meta.get("format") != FORMAT_NAME:
        raise ValueError(f"{str(path)!r} is not a puckboard recording")
    if int(meta.get("version", 0)) > FORMAT_VERSION:
        raise ValueError(
            f"{str(path)!r} uses recording format {meta['version']}; this puckboard reads "
            f"up to {FORMAT_VERSION}: upgrade puckboard"
        )
    if int(meta.get("version", 0)) < OLDEST_FORMAT_VERSION:
        raise ValueError(
            f"{str(path)!r} uses recording format {meta.get('version')}, which this puckboard "
            f"no longer reads (formats {OLDEST_FORMAT_VERSION} to {FORMAT_VERSION}): record "
            "the run again"
        )
    missing = set(_ARRAYS) - set(arrays)
    if missing:
        raise ValueError(f"recording {str(path)!r} lacks arrays: {', '.join(sorted(missing))}")
    try:
        decisions = Decisions.from_arrays(meta, arrays)
        return Recording(meta=meta, decisions=decisions, **{k: arrays[k] for k in _ARRAYS})
    except (ValueError, TypeError, KeyError) as exc:
        raise ValueError(f"{str(path)!r} is a damaged puckboard recording: {exc}") from None


class Recorder:
    """Records the robots of a run from the blackboard, one row per control cycle.

    Use it as an episode (or control loop) observer: ``recorder(episode)`` after every
    cycle samples the keys in :data:`RECORDED_KEYS` for every robot; :meth:`close`
    (registered as a close observer by :meth:`attach`) finishes the recording and, when
    ``path`` was given, writes it, so a run that ends in an error or Ctrl-C still leaves
    its recording behind.
    """

    def __init__(
        self,
        robot_names: Sequence[str],
        *,
        path: str | os.PathLike[str] | None = None,
        scene: Scene | None = None,
        meta: Mapping[str, Any] | None = None,
        robot_layers: Mapping[str, Sequence[str]] | None = None,
        capacity: int = 1024,
        events: Callable[[], list[dict[str, Any]]] | None = None,
        controllers: Mapping[str, Any] | None = None,
    ) -> None:
        if not robot_names:
            raise ValueError("a Recorder needs at least one robot name")
        self.robot_names = tuple(robot_names)
        self.path = None if path is None else Path(path)
        if self.path is not None and self.path.suffix.lower() != ".npz":
            raise ValueError(f"recordings are saved as .npz files, got {str(self.path)!r}")
        self.scene = scene
        n = len(self.robot_names)
        self._layer_table: dict[str, int] = {}
        self.robot_layers = {k: tuple(v) for k, v in (robot_layers or {}).items()}
        for layers in self.robot_layers.values():
            for name in layers:
                self._layer_index(name)
        self.meta: dict[str, Any] = dict(meta or {})
        self.events = events
        self._prox_range: float | None = None
        self._n = 0
        cap = max(16, int(capacity))
        #: the arrays being filled, by name (:data:`_ARRAYS`), ``cap`` rows each
        self._data = {
            name: np.empty((cap,) if tail is None else (cap, n, *tail), dtype=dtype)
            for name, (dtype, tail) in _ARRAYS.items()
        }
        #: the arbiters' decisions, when the controllers are known (see .decisions)
        self._decisions = (
            None if not controllers else DecisionRecorder(self.robot_names, controllers, cap)
        )
        self._closed = False
        self.saved_path: Path | None = None

    # -- building from an episode ---------------------------------------------------------
    @classmethod
    def for_episode(
        cls,
        episode: RecordedRun,
        path: str | os.PathLike[str] | None = None,
        *,
        decisions: bool = True,
    ) -> Recorder:
        """A recorder for every robot of ``episode``, with its scene and run metadata and,
        unless ``decisions`` is false, what each robot's arbiter decided every tick."""
        names = list(getattr(episode, "controllers", {}) or episode.connection.adapters)
        controllers = getattr(episode, "controllers", {}) or {}
        scene = getattr(episode, "scene", None)
        robot_layers = {name: controller_layers(c) for name, c in controllers.items()}
        ctrl_names = sorted({getattr(c, "name", "") for c in controllers.values()} - {""})
        dt = getattr(getattr(episode, "loop", None), "period", None)
        duration = getattr(scene, "duration", None)
        capacity = 1024
        if dt and duration and math.isfinite(duration / dt):
            capacity = int(duration / dt) + 2
        colours = {}
        if scene is not None:
            for spec in getattr(scene, "robots", ()):
                colours[spec.name] = list(spec.colour)
        meta = {
            "scenario": getattr(scene, "name", None),
            "controller": ", ".join(ctrl_names) or None,
            "seed": getattr(episode, "seed", None),
            "backend": getattr(episode, "backend", None),
            "dt": dt,
            "colours": colours,
        }
        judge = getattr(episode, "judge", None)
        events = None
        if judge is not None and hasattr(judge, "events"):

            def events() -> list[dict[str, Any]]:
                return [e.to_dict() for e in judge.events]

        return cls(
            names,
            path=path,
            scene=scene,
            meta=meta,
            robot_layers=robot_layers,
            capacity=capacity,
            events=events,
            controllers=controllers if decisions else None,
        )

    def attach(self, episode: RecordedRun) -> Recorder:
        """Register as ``episode``'s cycle observer and close observer; returns ``self``."""
        episode.add_observer(self)
        episode.add_close_observer(self.close)
        return self

    # -- sampling --------------------------------------------------------------------------
    def __call__(self, episode: RecordedRun) -> None:
        board = episode.blackboard
        loop = getattr(episode, "loop", None)
        self.sample(board, fallback_time=getattr(loop, "time", None))

    def sample(self, board: Blackboard, *, fallback_time: float | None = None) -> None:
        """Append one row read from ``board`` (a :class:`~puckboard.blackboard.Blackboard`)."""
        if self._closed:
            return
        i = self._n
        data = self._data
        if i == len(data["time"]):
            self._grow()
        pose, prox, ground = data["pose"], data["proximity"], data["ground"]
        wheels, layer = data["wheels"], data["layer"]
        stamp = math.nan
        for r, name in enumerate(self.robot_names):
            snap = board.namespace(name).snapshot(RECORDED_KEYS)
            rec = snap.record("pose")
            if rec is not None:
                p = rec.value
                pose[i, r] = (p.x, p.y, p.theta)
            else:
                pose[i, r] = math.nan
            rec = snap.record("proximity")
            if rec is not None:
                prox[i, r] = rec.value.distance
                if self._prox_range is None:
                    self._prox_range = self.meta["prox_range"] = float(rec.value.range)
                stamp = rec.stamp if math.isnan(stamp) else stamp
            else:
                prox[i, r] = math.nan
            rec = snap.record("ground")
            ground[i, r] = rec.value.value if rec is not None else math.nan
            rec = snap.record("command/wheels")
            if rec is not None:
                wheels[i, r] = (rec.value.left, rec.value.right)
                stamp = rec.stamp if math.isnan(stamp) else stamp
            else:
                wheels[i, r] = math.nan
            rec = snap.record("command/layer")
            layer[i, r] = -1 if rec is None else self._layer_index(rec.value)
        if self._decisions is not None:
            self._decisions.sample(i)
        if math.isnan(stamp):
            stamp = fallback_time if fallback_time is not None else float(i)
        data["time"][i] = stamp
        self._n = i + 1

    def _layer_index(self, name: str) -> int:
        idx = self._layer_table.get(name)
        if idx is None:
            idx = self._layer_table[name] = len(self._layer_table)
        return idx

    def _grow(self) -> None:
        new = 2 * len(self._data["time"])
        for name, old in self._data.items():
            arr = np.empty((new, *old.shape[1:]), dtype=old.dtype)
            arr[: len(old)] = old
            self._data[name] = arr
        if self._decisions is not None:
            self._decisions.grow(new)

    # -- reading while recording ---------------------------------------------------------
    def __len__(self) -> int:
        return self._n

    @property
    def layer_names(self) -> tuple[str, ...]:
        """The layer table so far: ``layer`` values index it."""
        return tuple(self._layer_table)

    def arrays(self) -> dict[str, np.ndarray]:
        """Read-only views of the rows so far (no copies; valid until the next row)."""
        n = self._n
        out = {name: arr[:n] for name, arr in self._data.items()}
        for view in out.values():
            view.flags.writeable = False
        return out

    # -- finishing -------------------------------------------------------------------------

    def recording(self) -> Recording:
        """The rows so far as a :class:`Recording` (copies; recording may continue)."""
        n = self._n
        meta = dict(self.meta)
        meta.update(
            robots=list(self.robot_names),
            layer_names=list(self._layer_table),
            robot_layers={k: list(v) for k, v in self.robot_layers.items()},
            created=meta.get("created") or _dt.datetime.now(_dt.timezone.utc).isoformat(),
            puckboard=__version__,
            scene=None if self.scene is None else scene_to_json(self.scene),
            version=FORMAT_VERSION,
        )
        meta.setdefault("colours", {})
        if self.events is not None:
            try:
                meta["events"] = list(self.events())
            except Exception:
                log.exception("could not read the run's events for the recording")
        return Recording(
            **{name: arr[:n].copy() for name, arr in self._data.items()},
            meta=meta,
            decisions=None if self._decisions is None else self._decisions.decisions(n),
        )

    def close(self, _episode: RecordedRun | None = None) -> Recording:
        """Stop recording and, if a ``path`` was given, save. Idempotent; returns the
        recording."""
        rec = self.recording()
        if not self._closed:
            self._closed = True
            if self.path is not None:
                self.saved_path = rec.save(self.path)
                log.info("recording of %d cycles written to %s", len(rec), self.saved_path)
        return rec


def controller_layers(controller: Controller) -> tuple[str, ...]:
    """Names of every layer of ``controller`` in priority order (tree order), each once:
    the controller's own :attr:`~puckboard.behaviours.controller.Controller.every_layer`."""
    return tuple(dict.fromkeys(layer.name for layer in controller.every_layer))


# -- scenes as JSON ------------------------------------------------------------------------

def _json_default(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    raise TypeError(f"cannot store {type(value).__name__} in a recording's metadata")


def scene_to_json(scene: Scene) -> dict[str, Any]:
    """The scene as stored in a recording: the scene file's own JSON form."""
    from ..scenario.conversion import scene_to_dict

    return scene_to_dict(scene)


def scene_from_json(data: Mapping[str, Any]) -> Scene:
    """Rebuild the recorded :class:`~puckboard.scenario.scene.Scene` from the scene file's
    own form, read (and validated) by :func:`~puckboard.scenario.conversion.scene_from_dict`."""
    from ..scenario.conversion import scene_from_dict

    return scene_from_dict(data, source="recording")
