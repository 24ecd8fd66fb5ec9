"""The e-puck over advanced sercom (binary mode), on Bluetooth or USB.

* **e-puck2** (``model="e-puck2"``): one write per exchange,
  ``[-0x09][19-byte actuator block][-0x08][0]``, and one 103-byte reply: the same
  cycle GCtronic's own e-puck2 driver runs.
* **e-puck1** (``model="e-puck1"``): the individual commands
  ``[-'D' l r][-'N'][-'M'][-'Q'][-'a'][-'O'][0]`` in one write; the reply is the
  concatenation of 16 + 6 + 4 + 6 + 16 bytes.

The camera is ``-'I'`` on both: a 3-byte header (mode, width, height) and the pixels
(40×40 RGB565 by default on the robot; over Bluetooth at most 4056 bytes).

Binary replies carry no header, so the only way to notice garbage is a wrong length
(a timeout) or implausible values; either makes the link drain the line and ask again.
"""

from __future__ import annotations

import logging

import numpy as np
import numpy.typing as npt

from . import sercom_codec as sc
from .blocks import ActuatorBlock, ImplausibleDataError, SensorBlock
from .link import LinkBase, Reply, _Garbage
from .transport import Transport
from .units import ACC_COUNTS_PER_G

__all__ = ["SercomLink"]

log = logging.getLogger(__name__)

MODELS = ("e-puck2", "e-puck1")

# e-puck1 accelerometer: ≈800 counts per g around 2048 (GCtronic driver, Webots plugin).
_EPUCK1_ACC = (800.0, 2048.0)


class SercomLink(LinkBase):
    """Speaks advanced sercom; see the module docstring."""

    backend_name = "sercom"

    def __init__(
        self,
        transport: Transport,
        *,
        model: str = "e-puck2",
        timeout: float = 1.0,
        retries: int = 2,
        prox_count: int = 8,
        ground_count: int = 3,
    ) -> None:
        if model not in MODELS:
            raise ValueError(f"sercom model must be one of {', '.join(MODELS)}, got {model!r}")
        super().__init__(transport, timeout=timeout, retries=retries)
        self.model = model
        self.prox_count = prox_count
        self.ground_count = ground_count
        self.acc_scale = (ACC_COUNTS_PER_G, 0.0) if model == "e-puck2" else _EPUCK1_ACC
        # the all-sensors block carries the e-puck2's gyro; the e-puck1 commands read none
        self.has_gyro = model == "e-puck2"
        # Whatever the robot printed before binary mode (its welcome banner) is noise to us.
        transport.drain()

    # -- exchanges ---------------------------------------------------------------------
    def exchange(self, actuators: ActuatorBlock, *, sensors: bool, image: bool) -> Reply:
        items: list[tuple[int, bytes]] = []
        expect: list[int] = []
        if self.model == "e-puck2":
            items.append((sc.ALL_ACTUATORS, actuators.encode()))
            if sensors:
                items.append((sc.ALL_SENSORS, b""))
                expect.append(sc.ALL_SENSORS)
        else:
            items.append((sc.SET_SPEED, sc.encode_int16s((actuators.left, actuators.right))))
            if sensors:
                for cmd in (sc.GET_PROXIMITY, sc.GET_GROUND, sc.GET_STEPS,
                            sc.GET_ACCELEROMETER, sc.GET_AMBIENT):  # fmt: skip
                    items.append((cmd, b""))
                    expect.append(cmd)
        if image:
            items.append((sc.GET_IMAGE, b""))  # last: a long reply must not delay the others
        request = sc.encode_request(items)
        return self._attempt(
            "sercom exchange", lambda: self._exchange_once(request, expect, image), timed=sensors
        )

    def _exchange_once(self, request: bytes, expect: list[int], image: bool) -> Reply:
        stale = self.transport.discard_pending()
        if stale:
            log.info("discarded %d stale bytes from %s", stale, self.description)
        self.transport.write(request)
        parts: dict[int, bytes] = {}
        for cmd in expect:
            size = sc.reply_size(cmd, prox_count=self.prox_count, ground_count=self.ground_count)
            assert size is not None
            parts[cmd] = self.transport.read_exact(size, self.timeout)
        frame: npt.NDArray[np.uint8] | None = None
        if image:
            header = self.transport.read_exact(3, self.timeout)
            try:
                size = sc.camera_body_size(header)
            except ValueError as exc:
                raise ImplausibleDataError(str(exc)) from None
            body = self.transport.read_exact(size, self.timeout * 3)
            frame = sc.decode_camera(header, body)
        # A binary reply has no header: bytes beyond the expected length mean that what
        # we just read was shifted by garbage. Throw it all away and ask again.
        extra = self.transport.discard_pending()
        if extra:
            raise _Garbage(f"{extra} bytes more than the reply's length")
        block: SensorBlock | None = None
        if sc.ALL_SENSORS in parts:
            block = SensorBlock.decode(parts[sc.ALL_SENSORS])
        elif expect:
            block = self._epuck1_block(parts)
        return Reply(sensors=block, image=frame)

    def _epuck1_block(self, parts: dict[int, bytes]) -> SensorBlock:
        prox = sc.decode_int16s(parts[sc.GET_PROXIMITY])[:8]
        ground = sc.decode_int16s(parts[sc.GET_GROUND])[:3]
        steps = sc.decode_int16s(parts[sc.GET_STEPS], 2)
        acc = sc.decode_int16s(parts[sc.GET_ACCELEROMETER], 3)
        ambient = sc.decode_int16s(parts[sc.GET_AMBIENT])[:8]
        block = SensorBlock(
            acc=(acc[0], acc[1], acc[2]),
            proximity=tuple(prox),
            ambient=tuple(ambient),
            steps=(steps[0], steps[1]),
            ground=(ground[0], ground[1], ground[2]),
            selector=3,
        )
        block.check_plausible()
        return block
