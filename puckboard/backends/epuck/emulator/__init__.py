"""The e-puck's wire, served by a simulated robot (``puckboard emulate``).

An :class:`EmulatedRobot` answers the e-puck2 Wi-Fi protocol and advanced sercom from a
robot of the embedded simulator, through the same codecs and sensor blocks that
:class:`~puckboard.backends.epuck.EPuckReal` decodes, so both ends of each wire live in
one backend folder. :func:`open_endpoint` serves it on TCP or a pseudo-terminal. Running
a scene around it (pacing, the judge, the other robots' controllers) is
:class:`puckboard.control.emulation.Emulation`.
"""

from .endpoint import PROTOCOLS, EndpointInfo, open_endpoint
from .robot import EmulatedRobot
from .servers import PtyServer, TcpServer, pty_available
from .sessions import SercomSession, WifiSession

__all__ = [
    "PROTOCOLS",
    "EmulatedRobot",
    "EndpointInfo",
    "PtyServer",
    "SercomSession",
    "TcpServer",
    "WifiSession",
    "open_endpoint",
    "pty_available",
]
