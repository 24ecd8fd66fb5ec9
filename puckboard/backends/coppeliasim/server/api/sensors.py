"""Sensors: the IR proximity sensors and the vision sensors (light sensor, camera).

``sim.readProximitySensor`` returns the detected point in the sensor's frame (z along the
direction it looks), the handle of the object seen (:mod:`..seen`) and the surface
normal. CoppeliaSim handles sensors in each simulation step, so before the first step of
a run a sensor reads state -1, as an unhandled sensor does. ``ePuck_lightSensor`` is
16×2 pixels (:mod:`..vision`); images go out bottom row first, as CoppeliaSim sends them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .....records import VREP_ORDER
from ..clients import ClientState
from ..objects import PROXIMITY_SENSOR, VISION_SENSOR, ServedObject
from ..seen import nearest_in_sector
from ..vision import aux_packet, encode_image, light_sensor_image, resolution
from .names import CONSTANTS as _C
from .state import ApiError, ServedState

__all__ = ["SensorFunctions"]


class SensorFunctions(ServedState):
    """``sim.read/handleProximitySensor``, ``sim.read/handleVisionSensor`` and the image calls."""

    @property
    def sensors_handled(self) -> bool:
        """CoppeliaSim handles sensors in each simulation step: before the first step of a
        run (or while stopped) a sensor has no result and reads state -1."""
        return self.running and self.world.step_count > 0

    def read_proximity_sensor(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.readProximitySensor", PROXIMITY_SENSOR)
        nothing = [0.0, 0.0, 0.0]
        if not self.sensors_handled:
            return [-1, 0.0, nothing, -1, nothing]
        i = obj.robot
        assert i is not None
        ps = VREP_ORDER[obj.index]
        d = float(self.world.prox_distance[i, ps])
        profile = self.world.actual[i]
        if not d < profile.prox_range:
            return [0, 0.0, nothing, -1, nothing]
        seen = nearest_in_sector(
            self.scene, self.world.poses.tolist(), self.world.actual, i, ps,
            reach=max(d, profile.prox_max_distance) * 1.5,
        )  # fmt: skip
        if seen is None:  # rays saw what the sector misses: straight ahead, object unknown
            return [1, d, [0.0, 0.0, d], -1, [0.0, 0.0, -1.0]]
        sensor = self.world_frame(obj)
        apex = sensor.position
        towards = np.array([seen.point[0] - apex[0], seen.point[1] - apex[1], 0.0])
        length = float(np.linalg.norm(towards))
        direction = towards / length if length > 0 else sensor.rotation[:, 2]
        point = sensor.rotation.T @ (direction * d)
        normal = sensor.rotation.T @ np.array([seen.normal[0], seen.normal[1], 0.0])
        target = self.objects.detectable.get(seen.key)
        return [1, d, point.tolist(), target.handle if target else -1, normal.tolist()]

    def _image(self, obj: ServedObject) -> np.ndarray:
        """The sensor's image, rows in sending order (bottom row first)."""
        assert obj.robot is not None
        if obj.part == "light":
            return light_sensor_image(self.world, obj.robot)
        return self.world.render_camera(obj.robot)[::-1]

    def read_vision_sensor(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.readVisionSensor", VISION_SENSOR)
        if not self.sensors_handled:
            return [-1]
        return [0, aux_packet(self._image(obj)), []]

    def handle_vision_sensor(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.handleVisionSensor", VISION_SENSOR)
        return [0, aux_packet(self._image(obj)), []]

    def get_vision_sensor_res(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getVisionSensorRes", VISION_SENSOR)
        return [list(resolution(obj.part, self.scene))]

    def _window(
        self, obj: ServedObject, func: str, pos: tuple[int, int], size: tuple[int, int]
    ) -> np.ndarray:
        w, h = resolution(obj.part, self.scene)
        image = self._image(obj)
        x, y = pos
        sw, sh = size
        if sw <= 0 or sh <= 0:
            sw, sh = w, h
        if x < 0 or y < 0 or x + sw > w or y + sh > h:
            raise ApiError(
                f"{func}: window pos={[x, y]} size={[sw, sh]} lies outside the {w}×{h} image"
            )
        return image[y : y + sh, x : x + sw]

    def get_vision_sensor_img(
        self,
        client: ClientState,
        handle: int,
        options: int,
        _cutoff: float,
        pos: tuple[int, int],
        size: tuple[int, int],
    ) -> list[Any]:
        func = "sim.getVisionSensorImg"
        obj = self._object(handle, func, VISION_SENSOR)
        image = self._window(obj, func, pos, size)
        return [encode_image(image, options), list(resolution(obj.part, self.scene))]

    def get_vision_sensor_char_image(
        self, client: ClientState, handle: int, x: int, y: int, sw: int, sh: int, _cutoff: float
    ) -> list[Any]:
        func = "sim.getVisionSensorCharImage"
        obj = self._object(handle, func, VISION_SENSOR)
        image = self._window(obj, func, (x, y), (sw, sh))
        w, h = resolution(obj.part, self.scene)
        return [encode_image(image, 1 if _greyscale(handle) else 0), w, h]

    def get_vision_sensor_image(
        self, client: ClientState, handle: int, x: int, y: int, sw: int, sh: int, ret: int
    ) -> list[Any]:
        """The deprecated float image (0..1 per channel), as the V-REP-era scripts read it."""
        func = "sim.getVisionSensorImage"
        obj = self._object(handle, func, VISION_SENSOR)
        image = self._window(obj, func, (x, y), (sw, sh)).astype(float) / 255.0
        if _greyscale(handle):
            image = image.mean(axis=2)
        if ret == 1:
            return [np.rint(image * 255.0).astype(np.uint8).tobytes()]
        return [image.ravel().tolist()]


def _greyscale(handle: int) -> bool:
    """Whether a handle carries ``sim.handleflag_greyscale`` (the deprecated image calls)."""
    return handle > 0 and bool(handle & _C["handleflag_greyscale"])
