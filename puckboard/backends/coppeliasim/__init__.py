"""The CoppeliaSim (formerly V-REP) backend: both ends of the ZeroMQ remote API wire.

:class:`EPuckVRep` (:mod:`.adapter`) drives an e-puck in CoppeliaSim through the
official client (``coppeliasim-zmqremoteapi-client``, extra ``puckboard[coppeliasim]``)
over a :mod:`.link`, stepped by a :mod:`.stepper`, finding its objects by :mod:`.naming`;
:func:`open_coppeliasim` (:mod:`.factory`) connects a scene's robots. :mod:`.server` is
the stand-in that serves the embedded simulator over the same protocol (``puckboard
serve``), so the client can be tried, taught and tested without CoppeliaSim.
"""

from .adapter import EPuckVRep
from .factory import open_coppeliasim
from .link import DEFAULT_PORT

__all__ = ["DEFAULT_PORT", "EPuckVRep", "open_coppeliasim"]
