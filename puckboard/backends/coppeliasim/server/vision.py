"""The served vision sensors' images, byte for byte as CoppeliaSim sends them.

``ePuck_lightSensor`` is the stock model's ground sensor: an orthographic vision sensor
1.7 mm above the floor, looking down, **16 × 2 pixels over 22 mm** across the robot
(decoded V-REP model). The stock e-puck script (the thesis's Code 2.1) reads three of its
values, bytes 0, 21 and 93 of the RGB image (Lua's ``img[1]``, ``img[22]``, ``img[94]``):
pixel 0 and pixel 7 of the first row sent and pixel 15 of the second, whose centres lie
10.3 mm left, 0.7 mm left and 10.3 mm right of the sensor's middle — exactly where the
``epuck-vrep`` profile puts its three ground sensors. So those three pixels carry the
simulated ground sensors' readings (with their noise), and every other pixel is the
floor's noise-free brightness at its centre: a line follower reading the image bytes and
one reading the sense-all values see the same numbers.

Rows go out bottom row first, 3 bytes a pixel (RGB); option bit 0 makes it one byte a
pixel (the integer mean of R, G and B, as CoppeliaSim computes it), bit 1 appends an
alpha byte (255: every served pixel sees a surface nearer than any cut-off).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from ....scenario.scene import Scene
    from ....sim.world import World

__all__ = ["LIGHT_SENSOR_RES", "aux_packet", "encode_image", "light_sensor_image", "resolution"]

#: Resolution of the stock model's light sensor (decoded V-REP model).
LIGHT_SENSOR_RES = (16, 2)
#: Its width across the robot (m).
LIGHT_SENSOR_SPAN = 0.022
#: (row as sent, column) of the pixels the stock script reads: left, centre, right.
STOCK_PIXELS = ((0, 0), (0, 7), (1, 15))

Image = npt.NDArray[np.uint8]


def resolution(part: str, scene: Scene) -> tuple[int, int]:
    """Width and height (pixels) of a robot's served vision sensor ``part``: the light
    sensor's fixed 16×2, or the camera's size the scene asks for."""
    if part == "light":
        return LIGHT_SENSOR_RES
    w, h = scene.camera_size
    return int(w), int(h)


def light_sensor_image(world: World, robot: int) -> Image:
    """The light sensor's 2×16×3 image of robot ``robot``, rows in sending order."""
    w, h = LIGHT_SENSOR_RES
    profile = world.actual[robot]
    x, y, theta = (float(v) for v in world.poses[robot][:3])
    pitch = LIGHT_SENSOR_SPAN / w
    across = (np.arange(w) - (w - 1) / 2.0) * -pitch  # column 0 on the left (+y)
    along = (np.arange(h) - (h - 1) / 2.0) * pitch  # row 0 (sent first) nearer the axle
    forward = profile.ground_poses[1].x + along
    fx, ay = np.meshgrid(forward, across, indexing="ij")
    c, s = np.cos(theta), np.sin(theta)
    points = np.stack([x + c * fx - s * ay, y + s * fx + c * ay], axis=-1).reshape(-1, 2)
    grey = world.floor.brightness(points, None, world.ground_footprints[robot]).reshape(h, w)
    for (row, col), value in zip(STOCK_PIXELS, world.ground[robot].tolist()):
        grey[row, col] = value
    grey8 = np.rint(np.clip(grey, 0.0, 1.0) * 255.0).astype(np.uint8)
    return np.repeat(grey8[:, :, None], 3, axis=2)


def encode_image(image: Image, options: int) -> bytes:
    """``image`` (rows in sending order, H×W×3) as ``sim.getVisionSensorImg`` sends it."""
    if options & 1:
        summed = image.astype(np.uint16).sum(axis=2)
        pixels = (summed // 3).astype(np.uint8)[:, :, None]
    else:
        pixels = image
    if options & 2:
        alpha = np.full(pixels.shape[:2] + (1,), 255, dtype=np.uint8)
        pixels = np.concatenate([pixels, alpha], axis=2)
    return np.ascontiguousarray(pixels).tobytes()


def aux_packet(image: Image) -> list[Any]:
    """``sim.readVisionSensor``'s default auxiliary packet: the minimum, maximum and mean
    of intensity, red, green, blue and depth over the image (0..1). The served sensors
    have no depth buffer: depth is 0 (every pixel sees a surface)."""
    rgb = image.reshape(-1, 3).astype(float) / 255.0
    channels = np.column_stack([rgb.mean(axis=1), rgb, np.zeros(len(rgb))])
    return [
        *channels.min(axis=0).tolist(),
        *channels.max(axis=0).tolist(),
        *channels.mean(axis=0).tolist(),
    ]
