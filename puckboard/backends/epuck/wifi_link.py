"""The e-puck2 over Wi-Fi: one 0x80 command per exchange, then the packets it asked for."""

from __future__ import annotations

import time

import numpy as np
import numpy.typing as npt

from .blocks import ActuatorBlock, SensorBlock
from .link import LinkBase, Reply, _Garbage
from .transport import Transport, TransportTimeout
from .units import ACC_COUNTS_PER_G
from .wifi_codec import EMPTY, IMAGE, SENSORS, PacketFramer, WifiCommand, decode_image

__all__ = ["WifiLink"]

# A frame is 38 kB: on a weak Wi-Fi link it takes far longer than a sensor packet
# (GCtronic's users measured 0.13 s median, 0.4 s mean), so images get their own timeout.
_IMAGE_TIMEOUT_FACTOR = 3.0


class WifiLink(LinkBase):
    """Speaks the Wi-Fi protocol (see :mod:`~puckboard.backends.epuck.wifi_codec`)."""

    backend_name = "epuck2-wifi"
    acc_scale = (ACC_COUNTS_PER_G, 0.0)
    has_gyro = True  # Wi-Fi is the e-puck2's: its sensor packet carries the gyro

    def __init__(self, transport: Transport, *, timeout: float = 1.0, retries: int = 2) -> None:
        super().__init__(transport, timeout=timeout, retries=retries)
        self._framer = PacketFramer()

    def exchange(self, actuators: ActuatorBlock, *, sensors: bool, image: bool) -> Reply:
        command = WifiCommand(actuators, image=image, sensors=sensors).encode()
        return self._attempt(
            "Wi-Fi exchange", lambda: self._exchange_once(command, sensors, image), timed=sensors
        )

    def _exchange_once(self, command: bytes, sensors: bool, image: bool) -> Reply:
        self._framer.clear()
        self.transport.discard_pending()  # late replies to an exchange that timed out
        self.transport.write(command)
        timeout = self.timeout * (_IMAGE_TIMEOUT_FACTOR if image else 1.0)
        deadline = time.monotonic() + timeout
        block: SensorBlock | None = None
        frame: npt.NDArray[np.uint8] | None = None
        got_empty = False
        while True:
            have_all = (not sensors or block is not None) and (not image or frame is not None)
            if have_all and (sensors or image or got_empty):
                break
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TransportTimeout(
                    f"no complete reply from {self.description} within {timeout:.2f} s"
                )
            chunk = self.transport.read_exact(self._framer.needed(), remaining)
            self._framer.feed(chunk)
            for pid, payload in self._framer.packets():
                if pid == SENSORS:
                    block = SensorBlock.decode(payload)
                elif pid == IMAGE:
                    frame = decode_image(payload)
                elif pid == EMPTY:
                    got_empty = True
            if self._framer.skipped:
                skipped, self._framer.skipped = self._framer.skipped, 0
                if self._framer.rejected:
                    self._framer.rejected = 0
                raise _Garbage(f"{skipped} bytes that start no packet")
        # The robot sends nothing unasked: bytes beyond the reply mean the packets we
        # just accepted were cut out of a shifted stream. Throw them away and ask again.
        extra = self._framer.pending() + self.transport.discard_pending()
        if extra:
            raise _Garbage(f"{extra} bytes after the reply")
        return Reply(sensors=block, image=frame)
