"""The CoppeliaSim (formerly V-REP) backend: both ends of the ZeroMQ remote API wire.

:class:`EPuckVRep` drives an e-puck in CoppeliaSim through the official client
(``coppeliasim-zmqremoteapi-client``, extra ``puckboard[coppeliasim]``);
:mod:`.server` is the stand-in that serves the embedded simulator over the same
protocol (``puckboard serve``), so the client can be tried, taught and tested without
CoppeliaSim.
"""

from .adapter import DEFAULT_PORT, EPuckVRep, open_coppeliasim

__all__ = ["DEFAULT_PORT", "EPuckVRep", "open_coppeliasim"]
