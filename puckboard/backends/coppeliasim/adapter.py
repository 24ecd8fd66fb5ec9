"""EPuckVRep: an e-puck in CoppeliaSim (or ``puckboard serve``) over the ZeroMQ remote API.

This is the source framework's EPuckVRep, moved from the legacy ``simx`` API to the
remote API of current CoppeliaSim (protocol version 2, CoppeliaSim ≥ 4.6), spoken by
the official client through a :class:`~.link.RemoteLink` (a deadline on every call, one
connection for many robots) and stepped by a :class:`~.stepper.RemoteStepper`; the robot
is found by either style of name (:mod:`.naming`). What the adapter itself adds:

* **Sense-all.** If the model's script has the ``puckboardSenseAll`` function (``puckboard
  serve`` has it; docs/coppeliasim.md gives the Lua for CoppeliaSim), every sensor comes
  in one round trip. Otherwise each sensor is read with its own calls (8 for the IR ring).
* **SI records** in the real e-puck's sensor order; the V-REP model's order
  (``ePuck_proxSensor1`` = left side) is converted here. Joint angles, which CoppeliaSim
  wraps to (-π, π], are unwrapped into encoders that never wrap (assuming a wheel turns
  less than half a turn between two reads: 0.05 s at top speed is 0.35 rad). The camera
  image is turned upright (CoppeliaSim sends the bottom row first).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ...blackboard import Blackboard, MissingValueError, Namespace
from ...errors import AdapterError, ConnectionLostError
from ...profile import EPUCK2, RobotProfile
from ...records import (
    VREP_ORDER,
    CameraImage,
    Ground,
    Pose,
    Proximity,
    Sensor,
    WheelEncoders,
    WheelSpeeds,
)
from ..base import RobotAdapter
from .link import DEFAULT_PORT, RemoteLink
from .naming import robot_object_names, show_name
from .stepper import RemoteStepper

__all__ = ["SENSE_ALL_FUNCTION", "EPuckVRep"]

log = logging.getLogger(__name__)

#: Name of the sense-all script function in the e-puck model's child script.
SENSE_ALL_FUNCTION = "puckboardSenseAll"
#: The stock model's light sensor: 16×2 pixels, of which its script reads three (as pixel
#: indices into the greyscale image as sent): left, centre, right.
STOCK_LIGHT_SENSOR_RES = (16, 2)
STOCK_LIGHT_PIXELS = (0, 7, 31)
#: Name of the both-wheels script function (present when the sense-all reply has api >= 1).
SET_WHEELS_FUNCTION = "puckboardSetWheels"
SCRIPTTYPE_CHILD = 1
HANDLE_WORLD = -1

# ps index → V-REP sensor index (0 = ePuck_proxSensor1)
_PS_FROM_VREP = np.array(VREP_ORDER)
_VREP_FROM_PS = np.argsort(_PS_FROM_VREP)


class EPuckVRep(RobotAdapter):
    """One e-puck of a CoppeliaSim scene; see the module docstring.

    ``object_path`` is the model's name or alias path (``"ePuck"``, ``"ePuck#0"``,
    ``"/ePuck[1]"``). Pass ``link`` and ``stepper`` to share one connection between
    robots (:func:`open_coppeliasim` does); otherwise the adapter opens its own to
    ``host:port`` and closes it with itself. ``sense_mode`` is ``"auto"`` (the sense-all
    script function when the model has it), ``"script"`` (required) or ``"calls"`` (one
    call per sensor object, as without it). ``heading_offset`` (rad) is added to the
    model's yaw, for scenes whose model does not face its x axis.
    """

    backend_name = "coppeliasim"
    available_sensors = frozenset(
        {
            Sensor.PROXIMITY,
            Sensor.GROUND,
            Sensor.ENCODERS,
            Sensor.WHEEL_SPEEDS,
            Sensor.POSE,
            Sensor.CAMERA,
        }
    )

    def __init__(
        self,
        name: str = "epuck",
        *,
        object_path: str = "ePuck",
        host: str = "127.0.0.1",
        port: int = DEFAULT_PORT,
        timeout: float = 5.0,
        link: RemoteLink | None = None,
        stepper: RemoteStepper | None = None,
        profile: RobotProfile = EPUCK2,
        blackboard: Blackboard | Namespace | None = None,
        command_timeout: float | None = None,
        sense_mode: str = "auto",
        heading_offset: float = 0.0,
    ) -> None:
        if sense_mode not in ("auto", "script", "calls"):
            raise ValueError(f"sense_mode must be 'auto', 'script' or 'calls', got {sense_mode!r}")
        self._own_link = link is None
        self.link = link if link is not None else RemoteLink(host, port, timeout)
        self._own_stepper = stepper is None
        try:
            super().__init__(
                name,
                profile=profile,
                blackboard=blackboard,
                stepper=stepper if stepper is not None else RemoteStepper(self.link),
                command_timeout=command_timeout,
            )
            self.object_path = object_path
            self.heading_offset = float(heading_offset)
            self.handles = self._find_objects(object_path)
            self._script = self._find_sense_script(sense_mode)
        except BaseException:
            if self._own_link:
                self.link.close()
            raise
        self._enc_last: np.ndarray | None = None
        self._enc_speed: np.ndarray | None = None
        self._enc_time = 0.0
        self._enc_total = np.zeros(2)

    @property
    def remote_stepper(self) -> RemoteStepper:
        assert isinstance(self.stepper, RemoteStepper)
        return self.stepper

    # -- discovery ---------------------------------------------------------------------------
    def _lookup(self, name: Any) -> int | None:
        path, options = (name[0], {"index": name[1]}) if isinstance(name, tuple) else (name, None)
        try:
            args = [path] if options is None else [path, options]
            handle = self.link.call("sim.getObject", args)
        except ConnectionLostError:
            raise
        except AdapterError:
            return None
        return int(handle) if isinstance(handle, int) and handle >= 0 else None

    def _find_objects(self, object_path: str) -> dict[str, Any]:
        tried: list[str] = []
        for names in robot_object_names(object_path):
            found: dict[str, Any] = {}
            missing: list[str] = []
            for part, name in names.items():
                if part == "prox":
                    handles = [self._lookup(n) for n in name]
                    found[part] = handles
                    missing += [show_name(n) for n, h in zip(name, handles) if h is None]
                else:
                    found[part] = self._lookup(name)
                    if found[part] is None and part not in _OPTIONAL_PARTS:
                        missing.append(show_name(name))
                if part == "base" and found[part] is None:
                    break  # no such robot in this style: try the other one
            tried += [show_name(names["base"])] if found.get("base") is None else missing
            if not missing:
                log.debug("robot %r: found %s objects (%s)", self.name, object_path, names["base"])
                self._drop_absent_sensors(found, names)
                return found
            if found.get("base") is not None:
                raise AdapterError(
                    f"e-puck {object_path!r} in {self.link.endpoint} lacks objects: "
                    f"{', '.join(missing)}; is it the stock e-puck model?"
                )
        raise AdapterError(
            f"no e-puck {object_path!r} in the simulation at {self.link.endpoint}; looked for "
            f"{', '.join(tried)}. Copies of a model are named ePuck#0, ePuck#1 ... "
            "(alias paths /ePuck[1], /ePuck[2] ...); is the scene loaded?"
        )

    def _drop_absent_sensors(self, found: dict[str, Any], names: dict[str, Any]) -> None:
        """A model without a light sensor or camera still drives; those sensors go away."""
        for part, sensor in _OPTIONAL_PARTS.items():
            if found.get(part) is None:
                log.warning(
                    "robot %r: the model has no %s (%s); its %s sensor is not available",
                    self.name, part, show_name(names[part]), sensor.value,
                )  # fmt: skip
                self.available_sensors = self.available_sensors - {sensor}
                self.disable(sensor)

    def _find_sense_script(self, sense_mode: str) -> int | None:
        if sense_mode == "calls":
            return None
        script = None
        if self.link.has("getScript") and self.link.has("callScriptFunction"):
            try:
                script = self.link.call("sim.getScript", [SCRIPTTYPE_CHILD, self.handles["base"]])
                reply = self.link.call("sim.callScriptFunction", [SENSE_ALL_FUNCTION, script])
                if not isinstance(reply, dict) or "prox" not in reply:
                    script = None
                else:
                    api = reply.get("api", 0)
                    self._wheels_function = isinstance(api, int) and api >= 1
            except ConnectionLostError:
                raise
            except AdapterError as exc:
                log.debug("no sense-all script function: %s", exc)
                script = None
        if script is None:
            if sense_mode == "script":
                raise AdapterError(
                    f"e-puck {self.object_path!r} has no {SENSE_ALL_FUNCTION} script function; "
                    "add it to the model's script (docs/coppeliasim.md) or use sense_mode='calls'"
                )
            log.info(
                "robot %r: the model's script has no %s; reading each sensor with its own "
                "calls (slower; docs/coppeliasim.md shows how to add it)",
                self.name, SENSE_ALL_FUNCTION,
            )  # fmt: skip
        return int(script) if script is not None else None

    @property
    def sense_mode(self) -> str:
        """``"script"`` (one round trip for all sensors) or ``"calls"`` (one per object)."""
        return "script" if self._script is not None else "calls"

    # -- the adapter hooks -------------------------------------------------------------------
    def _read_sensors(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        if self._script is not None:
            data = self.link.call("sim.callScriptFunction", [SENSE_ALL_FUNCTION, self._script])
            return self._records_from_script(data, sensors)
        return self._records_from_calls(sensors)

    def _records_from_script(self, data: Any, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        if not isinstance(data, dict):
            raise AdapterError(f"{SENSE_ALL_FUNCTION} returned {type(data).__name__}, not a map")
        t = data.get("t")
        if isinstance(t, (int, float)) and self.stepper is not None:
            self.remote_stepper.note_time(t)
        out: dict[Sensor, Any] = {}
        for s in sensors:
            if s is Sensor.PROXIMITY:
                rng = float(data.get("range", self.profile.prox_range))
                vrep = np.asarray(data["prox"], dtype=float)
                raw = data.get("proxRaw")
                out[s] = self._proximity(vrep, None if raw is None else np.asarray(raw, float), rng)
            elif s is Sensor.GROUND:
                out[s] = _ground(np.asarray(data["ground"], dtype=float))
            elif s is Sensor.ENCODERS:
                if "encoders" in data:  # accumulated by the model's script: never wraps
                    left, right = data["encoders"]
                    out[s] = WheelEncoders(float(left), float(right))
                else:
                    out[s] = self._encoders(data["joints"], data.get("speeds"), t)
            elif s is Sensor.WHEEL_SPEEDS:
                left, right = data["speeds"]
                out[s] = WheelSpeeds(float(left), float(right))
            elif s is Sensor.POSE:
                x, y, theta = data["pose"]
                out[s] = self._pose(float(x), float(y), float(theta))
        return out

    def _records_from_calls(self, sensors: frozenset[Sensor]) -> dict[Sensor, Any]:
        call = self.link.call
        h = self.handles
        out: dict[Sensor, Any] = {}
        for s in sensors:
            if s is Sensor.PROXIMITY:
                rng = self.profile.prox_range
                vrep = np.full(8, rng)
                for k, handle in enumerate(h["prox"]):
                    res, dist, *_ = call("sim.readProximitySensor", [handle])
                    if res and res > 0 and dist < rng:
                        vrep[k] = max(0.0, float(dist))
                out[s] = self._proximity(vrep, None, rng)
            elif s is Sensor.GROUND:
                out[s] = _ground(self._ground_from_image())
            elif s is Sensor.ENCODERS:
                angles = [
                    call("sim.getJointPosition", [h["left"]]),
                    call("sim.getJointPosition", [h["right"]]),
                ]
                speeds = [
                    call("sim.getJointVelocity", [h["left"]]),
                    call("sim.getJointVelocity", [h["right"]]),
                ]
                t = self.stepper.time if self.stepper is not None else None
                out[s] = self._encoders(angles, speeds, t)
            elif s is Sensor.WHEEL_SPEEDS:
                out[s] = WheelSpeeds(
                    float(call("sim.getJointVelocity", [h["left"]])),
                    float(call("sim.getJointVelocity", [h["right"]])),
                )
            elif s is Sensor.POSE:
                pose = call("sim.getObjectPose", [h["base"], HANDLE_WORLD])
                x, y, _, qx, qy, qz, qw = (float(v) for v in pose)
                yaw = math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
                out[s] = self._pose(x, y, yaw)
        return out

    def _ground_from_image(self) -> np.ndarray:
        """Three pixels of the light sensor (greyscale): left, centre, right.

        The stock model's 16×2 sensor is read where its script reads it (bytes 0, 21 and
        93 of the RGB image: pixels 0 and 7 of the first row sent, pixel 15 of the second);
        any other resolution at the ends and the middle of its middle row.
        """
        image, res = self.link.call("sim.getVisionSensorImg", [self.handles["light"], 1])
        w, hgt = int(res[0]), int(res[1])
        pixels = np.frombuffer(image, dtype=np.uint8)
        if pixels.size != w * hgt:
            raise AdapterError(
                f"light sensor image of {pixels.size} bytes does not match its resolution {w}×{hgt}"
            )
        if (w, hgt) == STOCK_LIGHT_SENSOR_RES:
            return pixels[list(STOCK_LIGHT_PIXELS)].astype(float) / 255.0
        row = pixels.reshape(hgt, w)[hgt // 2]
        return row[[0, w // 2, w - 1]].astype(float) / 255.0

    def _proximity(self, vrep: np.ndarray, raw_vrep: np.ndarray | None, rng: float) -> Proximity:
        distance = np.clip(vrep[_VREP_FROM_PS], 0.0, rng)
        if raw_vrep is not None:
            raw = raw_vrep[_VREP_FROM_PS]
        else:
            # what a real e-puck would send for that distance (0 for nothing)
            from ...ir_response import calibrated_from_distance

            raw = calibrated_from_distance(np.where(distance < rng, distance, np.inf))
        return Proximity(distance, raw, rng)

    def _encoders(
        self, wrapped: Sequence[float], speeds: Sequence[float] | None, t: Any
    ) -> WheelEncoders:
        """Unwrap joint angles (CoppeliaSim wraps them to (-π, π]) into encoders.

        The turn between two reads is taken as the one closest to what the wheel speeds
        predict (mean of the two reads' speeds times the elapsed simulation time); without
        speeds or time, as the smallest turn. Exact while the wheel speed changes by less
        than π rad between reads in total.
        """
        now = np.array([float(wrapped[0]), float(wrapped[1])])
        speed = None if speeds is None else np.array([float(speeds[0]), float(speeds[1])])
        if self._enc_last is None:
            self._enc_total = now.copy()  # a run opened at t = 0 starts at 0, as embedded
        else:
            predicted = np.zeros(2)
            if speed is not None and self._enc_speed is not None and isinstance(t, (int, float)):
                predicted = 0.5 * (speed + self._enc_speed) * (float(t) - self._enc_time)
            delta = now - self._enc_last - predicted
            self._enc_total += predicted + np.remainder(delta + math.pi, math.tau) - math.pi
        self._enc_last = now
        self._enc_speed = speed
        self._enc_time = float(t) if isinstance(t, (int, float)) else 0.0
        return WheelEncoders(float(self._enc_total[0]), float(self._enc_total[1]))

    def _pose(self, x: float, y: float, yaw: float) -> Pose:
        return Pose(x, y, math.remainder(yaw + self.heading_offset, math.tau), ground_truth=True)

    def _write_wheels(self, left: float, right: float) -> None:
        last_try = self.closed or self._closing
        if self._wheels_function and self._script is not None:
            self.link.call(
                "sim.callScriptFunction",
                [SET_WHEELS_FUNCTION, self._script, left, right],
                last_try=last_try,
            )
        else:
            self.link.call(
                "sim.setJointTargetVelocity", [self.handles["left"], left], last_try=last_try
            )
            self.link.call(
                "sim.setJointTargetVelocity", [self.handles["right"], right], last_try=last_try
            )
        if not last_try:
            self._publish_layer()

    def _publish_layer(self) -> None:
        """Tell the simulation which layer drives this robot, as the string signal
        ``<model name>.layer`` (``ePuck#0.layer``), so a viewer of the served world (the
        web view of ``puckboard serve --web``) can show it. One call, only when the layer
        changes; a simulator without signals or names simply never gets it."""
        try:
            layer = self.ns.get("command/layer").value
        except MissingValueError:
            return
        if layer != self._published_layer:
            self._published_layer = layer
            self._set_signal("layer", layer)
        if self._tree_text is not None and self._tree_text != self._published_tree:
            self._published_tree = self._tree_text
            self._set_signal("tree", self._tree_text)

    def show_tree(self, text: str) -> None:
        """The controller's behaviour tree with every node's status at this tick, as
        JSON, to publish with the layer as the string signal ``<model>.tree`` (when it
        changes) so the served world's web view can draw it."""
        self._tree_text = text

    def _set_signal(self, name: str, value: str) -> None:
        try:
            if self._model_name is None:
                self._model_name = str(self.link.call("sim.getObjectName", [self.handles["base"]]))
            self.link.call("sim.setStringSignal", [f"{self._model_name}.{name}", value])
        except ConnectionLostError:
            raise
        except AdapterError as exc:
            log.debug("%s signal not published: %s", name, exc)

    def _read_camera(self) -> CameraImage:
        image, res = self.link.call("sim.getVisionSensorImg", [self.handles["camera"]])
        w, h = int(res[0]), int(res[1])
        pixels = np.frombuffer(image, dtype=np.uint8)
        if pixels.size == w * h * 3:
            frame = pixels.reshape(h, w, 3)
        elif pixels.size == w * h:
            frame = np.repeat(pixels.reshape(h, w, 1), 3, axis=2)
        else:
            raise AdapterError(
                f"camera image of {pixels.size} bytes does not match its resolution {w}×{h}"
            )
        return CameraImage(frame[::-1])  # bottom row first → upright

    _closing = False
    _wheels_function = False
    _published_layer: str | None = None
    _tree_text: str | None = None
    _published_tree: str | None = None
    _model_name: str | None = None

    def close(self) -> None:
        self._closing = True
        super().close()

    def _close(self) -> None:
        if self._own_stepper:
            self.remote_stepper.release()
        if self._own_link:
            self.link.close()


#: Parts a model may lack (the robot still drives) and the sensor each one provides.
_OPTIONAL_PARTS = {"light": Sensor.GROUND, "camera": Sensor.CAMERA}


def _ground(value: np.ndarray) -> Ground:
    v = np.clip(value, 0.0, 1.0)
    return Ground(v, v * 1023.0)
