"""Backends: one adapter contract for the embedded simulator, CoppeliaSim and the real e-puck.

Each backend lives in one place, both ends of its wire together (as gpiozero keeps a pin
backend and its mock in one module):

* :mod:`.embedded` — the embedded simulator (the default);
* :mod:`.coppeliasim` — ``EPuckVRep``, the CoppeliaSim client, and in
  :mod:`.coppeliasim.server` the stand-in server ``puckboard serve``;
* :mod:`.epuck` — ``EPuckReal``, the physical e-puck over Wi-Fi or sercom, and in
  :mod:`.epuck.emulator` the emulated robot ``puckboard emulate`` serves;
* :mod:`.fake` — a robot whose sensors a test sets by hand.

Only the contract, the registry and the fake robot are imported here; the other backends
load on demand. No backend knows a controller or the control loop.
"""

from .base import Connection, RobotAdapter, Stepper, declare_robot_keys
from .fake import FakeAdapter, FakeClock
from .registry import BACKENDS, open_backend, register_backend

__all__ = [
    "BACKENDS",
    "Connection",
    "FakeAdapter",
    "FakeClock",
    "RobotAdapter",
    "Stepper",
    "declare_robot_keys",
    "open_backend",
    "register_backend",
]
