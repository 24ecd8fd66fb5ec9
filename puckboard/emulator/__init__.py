"""A protocol-level e-puck emulator backed by the embedded simulator (``puckboard emulate``).

:class:`Emulation` serves the first robot of a scene over the e-puck2 Wi-Fi protocol or
advanced sercom, paced in real time, so code written for the real robot
(:class:`~puckboard.adapters.real.EPuckReal`, or any other client of those protocols)
can be tried without one.
"""

from .emulation import PROTOCOLS, Emulation, EmulationInfo
from .robot import EmulatedRobot
from .servers import PtyServer, TcpServer, pty_available
from .sessions import SercomSession, WifiSession

__all__ = [
    "PROTOCOLS",
    "EmulatedRobot",
    "Emulation",
    "EmulationInfo",
    "PtyServer",
    "SercomSession",
    "TcpServer",
    "WifiSession",
    "pty_available",
]
