"""What each robot's arbiter decided, tick by tick: the part of a recording a replay's
tree panel shows.

Per robot and control tick a recording (format 3) keeps

* the status of every node of the controller's behaviour tree after the tick (a
  :class:`~puckboard.behaviours.tracing.TreeTrace`: not asked, ``FAILURE`` = asked and
  did not apply, ``RUNNING`` = applies or holds, ...), one ``int8`` per node;
* the blackboard values the layers read during that tick, taken from the very snapshot
  the controller handed its layers (``controller.context.frame``), with their ages and whether
  they were fresh or stale.

Together with the ``layer`` array (which layer drove) that answers "who wanted the
wheels, who got them, and on what evidence" for any instant of a run.

On disk (names in the recording's ``.npz``; R keys read, K nodes of the largest tree):

===============  ==========  =======  ==========================================
array            shape       dtype    meaning
===============  ==========  =======  ==========================================
``tree``         T×N×K       int8     node status, see ``meta["tree_status"]``
``read_age``     T×N×R       float32  age (s) of each read key at the tick; NaN: missing
``read_status``  T×N×R       int8     0 missing (or not read), 1 fresh, 2 stale
``read_<j>``     T×N×W       float32  key j's value as numbers (NaN: none)
===============  ==========  =======  ==========================================

``meta["trees"]`` holds each robot's nodes (see
:func:`~puckboard.behaviours.tracing.tree_nodes`), ``meta["reads"]`` each key's
``key``, ``type``, ``labels``, ``unit`` and the ``array`` holding its values (``null``
for values that are not numbers, such as a camera image: their age is kept),
``meta["robot_reads"]`` the keys each robot's controller reads.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..behaviours.tracing import STATUS_NAMES, TreeTrace, trace

if TYPE_CHECKING:
    from ..behaviours.controller import Controller

__all__ = ["DecisionRecorder", "Decisions"]

log = logging.getLogger(__name__)

_UNITS = {
    "Proximity": "m", "Ground": "", "Light": "raw", "Pose": "m, m, rad",
    "WheelCommand": "rad/s", "WheelSpeeds": "rad/s", "WheelEncoders": "rad",
    "Acceleration": "m/s²", "AngularVelocity": "rad/s",
}  # fmt: skip

Converter = Callable[[Any], Any]


def value_converter(value: Any) -> tuple[Converter, list[str]] | None:
    """How to store values like ``value`` as a row of numbers, and the row's labels;
    ``None`` when they are not numbers (text, images)."""
    names = getattr(type(value), "_names", None)
    field = getattr(type(value), "_field", None)
    if names and field:  # Proximity, Ground, Light: named sensors over one array
        return (lambda v: getattr(v, field)), list(names)
    if isinstance(value, (bool, str, bytes)):
        return None
    if isinstance(value, (int, float, np.integer, np.floating)):
        return (lambda v: float(v)), [""]
    if isinstance(value, np.ndarray) and value.dtype.kind in "biuf" and 0 < value.size <= 64:
        return (lambda v: np.ravel(v)), [str(k) for k in range(value.size)]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = [
            f.name for f in dataclasses.fields(value)
            if isinstance(getattr(value, f.name), (int, float, np.floating, np.integer))
            and not isinstance(getattr(value, f.name), bool)
        ]  # fmt: skip
        if fields:
            return (lambda v: [getattr(v, f) for f in fields]), fields
    return None


@dataclasses.dataclass
class Decisions:
    """The decisions of a recorded run; see the module docstring for the arrays."""

    trees: dict[str, list[dict[str, Any]]]
    status: npt.NDArray[np.int8]  # T×N×K
    reads: list[dict[str, Any]]  # per key: key, type, labels, unit, array
    robot_reads: dict[str, list[str]]
    age: npt.NDArray[np.float32]  # T×N×R
    fresh: npt.NDArray[np.int8]  # T×N×R
    values: dict[str, npt.NDArray[np.float32]]  # key → T×N×W

    @property
    def keys(self) -> tuple[str, ...]:
        return tuple(r["key"] for r in self.reads)

    def check(self, t: int, n: int) -> None:
        """Refuse arrays that do not fit ``t`` cycles of ``n`` robots."""
        named: list[tuple[str, np.ndarray]] = [
            ("tree", self.status), ("read_age", self.age), ("read_status", self.fresh),
            *self.values.items(),
        ]  # fmt: skip
        for name, arr in named:
            if arr.ndim != 3 or arr.shape[:2] != (t, n):
                raise ValueError(
                    f"recording array {name!r} has shape {arr.shape}, expected {t}×{n}×… "
                    f"for {t} cycles of {n} robots"
                )
        if self.age.shape[2] != len(self.reads) or self.fresh.shape != self.age.shape:
            raise ValueError("recording arrays 'read_age'/'read_status' do not match meta['reads']")

    def node_status(self, robot: str, index: int, tick: int) -> dict[str, str]:
        """Node name → status name for robot ``robot`` (the recording's robot ``index``)."""
        nodes = self.trees.get(robot) or []
        row = self.status[tick, index]
        return {node["name"]: STATUS_NAMES[int(code)] for node, code in zip(nodes, row)}

    # -- disk --------------------------------------------------------------------------------
    def to_arrays(
        self, same: Mapping[str, np.ndarray] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """The arrays and the meta entries that store these decisions. A key whose values
        equal one of the recording's own arrays (``same``: array name → array, such as
        ``proximity``) is stored as a reference to it (``meta["reads"][j]["array"]``
        names that array), not twice."""
        arrays: dict[str, np.ndarray] = {
            "tree": self.status, "read_age": self.age, "read_status": self.fresh,
        }  # fmt: skip
        reads = []
        for j, entry in enumerate(self.reads):
            entry = dict(entry)
            values = self.values.get(entry["key"])
            twin = next(
                (name for name, arr in (same or {}).items()
                 if values is not None and arr.shape == values.shape
                 and np.array_equal(arr, values, equal_nan=True)),
                None,
            )  # fmt: skip
            if values is None:
                entry["array"] = None
            elif twin is not None:
                entry["array"] = twin
            else:
                entry["array"] = f"read_{j}"
                arrays[entry["array"]] = values
            reads.append(entry)
        meta = {
            "trees": self.trees, "tree_status": list(STATUS_NAMES), "reads": reads,
            "robot_reads": self.robot_reads,
        }  # fmt: skip
        return arrays, meta

    @classmethod
    def from_arrays(
        cls, meta: Mapping[str, Any], arrays: Mapping[str, np.ndarray]
    ) -> Decisions | None:
        """The decisions stored in a loaded recording, or ``None`` if it has none
        (format 2, or a run recorded without its controllers)."""
        if "tree" not in arrays or "trees" not in meta:
            return None
        reads = [dict(r) for r in meta.get("reads") or []]
        values = {}
        for r in reads:
            name = r.get("array")
            if name:
                if name not in arrays:
                    raise ValueError(f"recording lacks the array {name!r} named in meta['reads']")
                values[r["key"]] = np.asarray(arrays[name], dtype=np.float32)
        return cls(
            trees={k: list(v) for k, v in dict(meta["trees"]).items()},
            status=np.asarray(arrays["tree"], dtype=np.int8),
            reads=reads,
            robot_reads={k: list(v) for k, v in dict(meta.get("robot_reads") or {}).items()},
            age=np.asarray(arrays.get("read_age", np.zeros((0, 0, 0))), dtype=np.float32),
            fresh=np.asarray(arrays.get("read_status", np.zeros((0, 0, 0))), dtype=np.int8),
            values=values,
        )


class DecisionRecorder:
    """Samples the decisions of ``controllers`` (robot name → controller) into
    preallocated arrays; :class:`~puckboard.recording.recorder.Recorder` calls :meth:`sample`
    once per recorded cycle, right after the controllers ticked."""

    def __init__(
        self, robot_names: Sequence[str], controllers: Mapping[str, Controller], capacity: int
    ) -> None:
        self.robot_names = tuple(robot_names)
        self.controllers = [controllers.get(name) for name in self.robot_names]
        self.traces: list[TreeTrace | None] = [
            None if c is None else trace(c) for c in self.controllers
        ]
        self._seen = [t.ticks if t is not None else 0 for t in self.traces]
        n = len(self.robot_names)
        width = max((len(t.nodes) for t in self.traces if t is not None), default=0)
        keys = sorted({k for c in self.controllers if c is not None for k in c.reads})
        self.keys = tuple(keys)
        index = {k: j for j, k in enumerate(keys)}
        self._robot_keys = [
            [] if c is None else [(index[k], k) for k in c.reads] for c in self.controllers
        ]
        self._status = np.zeros((capacity, n, width), dtype=np.int8)
        self._age = np.full((capacity, n, len(keys)), np.nan, dtype=np.float32)
        self._fresh = np.zeros((capacity, n, len(keys)), dtype=np.int8)
        self._values: list[np.ndarray | None] = [None] * len(keys)
        self._convert: list[Converter | None] = [None] * len(keys)
        self._reads: list[dict[str, Any]] = [
            {"key": k, "type": None, "labels": [], "unit": ""} for k in keys
        ]
        self._warned: set[str] = set()

    def sample(self, i: int) -> None:
        """Row ``i``: every robot's node statuses and the values its layers read."""
        for r, ctrl in enumerate(self.controllers):
            tr = self.traces[r]
            if tr is None or ctrl is None:
                continue
            if tr.ticks != self._seen[r]:
                self._status[i, r, : len(tr.status)] = tr.status
                self._seen[r] = tr.ticks
            else:  # the tree was not ticked (inputs stale): nobody was asked
                self._status[i, r] = 0
            frame = ctrl.context.frame  # what the layers were handed this tick
            if frame is None:
                continue
            snap = frame.snapshot
            now = snap.now
            for j, key in self._robot_keys[r]:
                rec = snap.record(key)
                if rec is None:
                    continue
                self._age[i, r, j] = now - rec.stamp
                self._fresh[i, r, j] = 1 if snap.status(key) == "fresh" else 2
                convert = self._convert[j]
                if convert is None:
                    convert = self._start_values(j, rec.value)
                if self._values[j] is not None:
                    try:
                        self._values[j][i, r] = convert(rec.value)  # type: ignore[index,misc]
                    except (ValueError, TypeError):
                        self._warn(key, rec.value)

    def _start_values(self, j: int, value: Any) -> Converter:
        """The first value of key ``j`` fixes how its values are stored."""
        found = value_converter(value)
        entry = self._reads[j]
        entry["type"] = type(value).__name__
        entry["unit"] = _UNITS.get(entry["type"], "")
        if found is None:
            self._convert[j] = _ignore
            return _ignore
        convert, labels = found
        entry["labels"] = labels
        cap, n = self._status.shape[:2]
        self._values[j] = np.full((cap, n, len(labels)), np.nan, dtype=np.float32)
        self._convert[j] = convert
        return convert

    def _warn(self, key: str, value: Any) -> None:
        if key not in self._warned:
            self._warned.add(key)
            log.warning("key %r changed its shape (%r): its values are not recorded", key, value)

    def grow(self, capacity: int) -> None:
        def grown(old: np.ndarray, fill: float) -> np.ndarray:
            arr = np.full((capacity, *old.shape[1:]), fill, dtype=old.dtype)
            arr[: len(old)] = old
            return arr

        self._status = grown(self._status, 0)
        self._age = grown(self._age, math.nan)
        self._fresh = grown(self._fresh, 0)
        self._values = [None if v is None else grown(v, math.nan) for v in self._values]

    def decisions(self, n: int) -> Decisions:
        """The first ``n`` rows, copied."""
        return Decisions(
            trees={
                name: list(tr.nodes)
                for name, tr in zip(self.robot_names, self.traces)
                if tr is not None
            },
            status=self._status[:n].copy(),
            reads=[dict(r) for r in self._reads],
            robot_reads={
                name: [k for _, k in keys]
                for name, keys, c in zip(self.robot_names, self._robot_keys, self.controllers)
                if c is not None
            },
            age=self._age[:n].copy(),
            fresh=self._fresh[:n].copy(),
            values={
                self.keys[j]: v[:n].copy() for j, v in enumerate(self._values) if v is not None
            },
        )


def _ignore(value: Any) -> None:
    return None
