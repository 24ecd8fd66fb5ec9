"""How fast EPuckReal talks to a robot, measured against the emulator over loopback.

``run_suite(steps)`` measures, for the Wi-Fi protocol and advanced sercom (over a TCP
socket, and over a pseudo-terminal where there is one), the median time of:

* ``sense_all``: one exchange for every sensor (Wi-Fi 0x80 + packet 0x02; sercom
  e-puck2 0x09 + 0x08);
* ``set_wheel_speeds``: one actuator exchange (Wi-Fi: answered with 0x03; sercom: no
  reply, so this times the write only);
* ``camera_image``: one frame (Wi-Fi 160×120 RGB565; sercom 40×40 RGB565).

Loopback figures are an upper bound: they show what the library and the emulator cost,
not what a radio link delivers (a real e-puck2 over Wi-Fi was measured at 2-7 frames/s
by others; Bluetooth carries ≈1 frame/s). Run it with
``puckboard bench --suite emulator``.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import Any

from .timing import REPEATS, seconds_per_call

__all__ = ["run_suite"]


def _median_ms(fn: Callable[[], Any], calls: int) -> float:
    return seconds_per_call(fn, calls) * 1e3


def _carriers() -> list[tuple[str, str | None]]:
    from ..backends.epuck.emulator.servers import pty_available

    out: list[tuple[str, str | None]] = [("wifi", None), ("sercom", "tcp")]
    if pty_available():
        out.append(("sercom", "pty"))
    return out


def run_suite(steps: int | None = None) -> dict[str, Any]:
    """Exchange times per protocol and carrier (median of 5 repeats, ms per call)."""
    from ..backends.epuck import open_sercom, open_wifi
    from ..control.emulation import Emulation

    calls = steps or 200
    out: dict[str, Any] = {"calls_per_repeat": calls, "repeats": REPEATS, "unit": "ms per call"}
    for protocol, serial in _carriers():
        em = Emulation("line-follow", protocol=protocol, serial=serial)
        thread = threading.Thread(target=em.run, args=(3600.0,), daemon=True)
        thread.start()
        try:
            opts = em.info.options
            conn = (
                open_wifi("line-follow", **opts)
                if protocol == "wifi"
                else open_sercom("line-follow", **opts)
            )
            with conn:
                robot = conn.adapters[em.robot.name]
                label = protocol if serial is None else f"{protocol}-{serial}"
                sense = _median_ms(robot.sense_all, calls)
                drive = _median_ms(functools.partial(robot.set_wheel_speeds, 1.0, 1.0), calls)
                camera = _median_ms(robot.camera_image, max(5, calls // 10))
                out[label] = {
                    "sense_all_ms": round(sense, 3),
                    "set_wheel_speeds_ms": round(drive, 3),
                    "camera_image_ms": round(camera, 3),
                    "sense_all_per_s": round(1e3 / sense, 1),
                    "frames_per_s": round(1e3 / camera, 1),
                }
        finally:
            em.stop()
            thread.join(5)
    return out
