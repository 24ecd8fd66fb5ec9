"""A link: one protocol spoken over one transport, as request/reply exchanges.

:class:`EPuckReal` does not care whether its robot is on Wi-Fi or on a serial line; it
asks its link for one *exchange*: "drive with these actuators, and send me the sensors
and/or an image". Each protocol implements that in as few round trips as it can (one
Wi-Fi command; one serial write). This module holds what all links share: the reply
type, the retry-and-resynchronise policy, the "broken link" state that makes every
call after a lost connection fail at once instead of waiting for another timeout, and
the timing of the link's own round trips (:attr:`LinkBase.round_trips`), which
``puckboard calibrate link`` reads.
"""

from __future__ import annotations

import logging
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, TypeVar

import numpy as np
import numpy.typing as npt

from ...errors import ConnectionLostError
from .blocks import ActuatorBlock, ImplausibleDataError, SensorBlock
from .transport import Transport, TransportTimeout

__all__ = ["ROUND_TRIPS_KEPT", "Link", "LinkBase", "Reply"]

log = logging.getLogger(__name__)

T = TypeVar("T")

#: How many of its latest round trips a link keeps: minutes of a 20 Hz loop, a few kB.
ROUND_TRIPS_KEPT = 4096


@dataclass(frozen=True)
class Reply:
    """What one exchange brought back (``None`` where nothing was asked for)."""

    sensors: SensorBlock | None = None
    image: npt.NDArray[np.uint8] | None = None


class Link(Protocol):
    backend_name: str
    description: str
    #: Accelerometer convention of this robot/protocol: (counts per g, zero offset).
    acc_scale: tuple[float, float]
    #: Whether the sensor blocks carry a gyro reading (the e-puck2's do).
    has_gyro: bool

    def exchange(self, actuators: ActuatorBlock, *, sensors: bool, image: bool) -> Reply: ...

    def close(self) -> None: ...


class LinkBase:
    """Retries, resynchronisation and failure state shared by the protocol links.

    ``timeout`` bounds each read; ``retries`` is how many times an exchange is repeated
    after a timeout or garbage (after draining the line) before the link gives up with
    :class:`~puckboard.errors.ConnectionLostError`. A lost connection (peer closed, device
    gone) is not retried: the link is marked broken and every later call fails fast.

    Every exchange that brings sensors back is timed, from the request leaving to the
    whole reply read (the successful attempt only), and kept in :attr:`round_trips`
    (seconds, the latest :data:`ROUND_TRIPS_KEPT`); ``clock`` is what times them.
    """

    backend_name = "real"

    def __init__(self, transport: Transport, *, timeout: float = 1.0, retries: int = 2) -> None:
        if timeout <= 0:
            raise ValueError(f"timeout must be positive seconds, got {timeout}")
        if retries < 0:
            raise ValueError(f"retries must be ≥ 0, got {retries}")
        self.transport = transport
        self.timeout = timeout
        self.retries = retries
        self.description = transport.description
        self.resyncs = 0
        self._broken: str | None = None
        self.clock: Callable[[], float] = time.perf_counter
        #: seconds each sensing exchange took, request to whole reply (latest last)
        self.round_trips: deque[float] = deque(maxlen=ROUND_TRIPS_KEPT)

    def _attempt(self, what: str, fn: Callable[[], T], *, timed: bool = False) -> T:
        if self._broken is not None:
            raise ConnectionLostError(
                f"the link to the robot ({self.description}) was lost earlier: {self._broken}"
            )
        last: Exception | None = None
        for attempt in range(self.retries + 1):
            try:
                if not timed:
                    return fn()
                start = self.clock()
                result = fn()
                self.round_trips.append(self.clock() - start)
                return result
            except (TransportTimeout, ImplausibleDataError, _Garbage) as exc:
                last = exc
                self.resyncs += 1
                log.warning(
                    "%s on %s failed (%s); resynchronising (attempt %d of %d)",
                    what, self.description, exc, attempt + 1, self.retries + 1,
                )  # fmt: skip
                try:
                    dropped = self.transport.drain()
                except ConnectionLostError as lost:
                    self._broken = str(lost)
                    raise
                if dropped:
                    log.info("dropped %d stray bytes from %s", dropped, self.description)
            except ConnectionLostError as exc:
                self._broken = str(exc)
                raise
        self._broken = f"{what} failed {self.retries + 1} times; last error: {last}"
        raise ConnectionLostError(
            f"the robot on {self.description} stopped answering sensibly: {self._broken}"
        ) from last

    @property
    def broken(self) -> bool:
        return self._broken is not None

    def close(self) -> None:
        self.transport.close()


class _Garbage(ValueError):
    """Bytes arrived that do not belong to the exchange in progress."""
