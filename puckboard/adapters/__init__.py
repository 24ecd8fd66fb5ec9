"""Robot adapters: one contract for the embedded simulator, CoppeliaSim and the real e-puck.

Only the contract and the fake robot are imported here; backends load on demand.
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
