"""An adapter's background threads and observers: sensing and the camera at their own
periods, and the callbacks told of each sensing cycle and each new image.

They are apart from :class:`~puckboard.backends.base.RobotAdapter`'s contract because a
controller never needs them: the control loop senses once per cycle itself. They serve
a viewer or a monitor that wants readings between cycles, and a real robot read on its
own clock. Every read still goes through the adapter's own calls (``sense_all``,
``camera_image``), so it holds the adapter's transport lock: a thread can never overlap
the controller's wheel command.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from typing import Any

from ..errors import AdapterClosedError
from ..records import CameraImage, Sensor

__all__ = ["CameraObserver", "SensingThreads", "SensorObserver"]

log = logging.getLogger(__name__)

# an observer is handed the adapter (a RobotAdapter; named Any here, since base.py
# imports this module and the import graph has no circle)
SensorObserver = Callable[[Any, frozenset[Sensor]], None]
CameraObserver = Callable[[Any, CameraImage], None]


class SensingThreads:
    """The threads and observers of one adapter (a base of ``RobotAdapter``).

    The adapter supplies ``name``, ``sense_all``, ``camera_image`` and ``_ensure_open``;
    it tells the observers after each sensing cycle and image through
    :meth:`_tell_sensor_observers` and :meth:`_tell_camera_observers`.
    """

    name: str

    def __init__(self) -> None:
        self._sensor_observers: list[SensorObserver] = []
        self._camera_observers: list[CameraObserver] = []
        self._threads: list[_PeriodicThread] = []

    # what the adapter supplies
    def sense_all(self) -> Any:
        raise NotImplementedError

    def camera_image(self) -> Any:
        raise NotImplementedError

    def _ensure_open(self) -> None:
        raise NotImplementedError

    # -- observers -------------------------------------------------------------------------
    def add_sensor_observer(self, observer: SensorObserver) -> None:
        """``observer(adapter, changed_sensors)`` after every sensing cycle."""
        self._sensor_observers.append(observer)

    def add_camera_observer(self, observer: CameraObserver) -> None:
        """``observer(adapter, image)`` after every new camera image."""
        self._camera_observers.append(observer)

    def _tell_sensor_observers(self, changed: frozenset[Sensor]) -> None:
        for obs in list(self._sensor_observers):
            _call_observer(obs, self, changed)

    def _tell_camera_observers(self, image: CameraImage) -> None:
        for obs in list(self._camera_observers):
            _call_observer(obs, self, image)

    # -- threads ---------------------------------------------------------------------------
    def start_sensing_thread(self, period: float = 0.05) -> None:
        """Run ``sense_all`` every ``period`` wall-clock seconds in a background thread."""
        self._start_thread("sensing", period, self.sense_all)

    def start_camera_thread(self, period: float = 0.2) -> None:
        """Refresh the camera image every ``period`` wall-clock seconds in a background thread."""
        self._start_thread("camera", period, self.camera_image)

    def _start_thread(self, what: str, period: float, fn: Callable[[], Any]) -> None:
        if period <= 0:
            raise ValueError(f"{what} thread period must be positive seconds, got {period}")
        self._ensure_open()
        if any(t.what == what and t.is_alive() for t in self._threads):
            raise RuntimeError(f"robot {self.name!r} already has a {what} thread")
        thread = _PeriodicThread(f"{self.name}-{what}", what, period, fn)
        self._threads.append(thread)
        thread.start()

    def stop_threads(self, timeout: float = 2.0) -> None:
        threads, self._threads = self._threads, []
        for t in threads:
            t.stop()
        for t in threads:
            if t is not threading.current_thread():
                t.join(timeout)


class _PeriodicThread(threading.Thread):
    """Calls ``fn`` every ``period`` seconds until stopped; logs (and survives) failures."""

    def __init__(self, name: str, what: str, period: float, fn: Callable[[], Any]) -> None:
        super().__init__(name=name, daemon=True)
        self.what = what
        self.period = period
        self.fn = fn
        self._stop_event = threading.Event()

    def stop(self) -> None:
        self._stop_event.set()

    def run(self) -> None:
        next_time = time.monotonic()
        failures = 0
        while not self._stop_event.is_set():
            try:
                self.fn()
                failures = 0
            except AdapterClosedError:
                return
            except Exception:
                failures += 1
                log.exception("%s thread %s failed (%d in a row)", self.what, self.name, failures)
                if failures >= 10:
                    log.error("%s thread %s gives up after 10 failures", self.what, self.name)
                    return
            next_time += self.period
            delay = next_time - time.monotonic()
            if delay < 0:  # overran: do not try to catch up with a burst
                next_time = time.monotonic()
                delay = 0
            self._stop_event.wait(delay)


def _call_observer(observer: Callable[..., None], *args: Any) -> None:
    try:
        observer(*args)
    except Exception:
        log.exception("observer %r failed", observer)
