"""The ZeroMQ remote API (protocol version 2), served by the embedded simulator.

CoppeliaSim's add-on "ZMQ remote API server" lets a client in any language call ``sim.*``
functions over a ZeroMQ REQ/REP pair, one CBOR map per message. This package speaks that
protocol for a served :class:`~puckboard.sim.world.World`, so the official client
(``coppeliasim-zmqremoteapi-client``) and
:class:`~puckboard.backends.coppeliasim.adapter.EPuckVRep` drive our simulator exactly as
they would drive CoppeliaSim, and a lecturer can serve one simulation to a whole class
(``puckboard serve``).

One concept per module:

* :mod:`.codec` — frames: CBOR decoding and validation of requests, encoding of replies;
* :mod:`.objects` — the served scene's object tree: handles, deprecated names, alias paths;
* :mod:`.frames` — 3-D rigid transforms in CoppeliaSim's forms (matrix, quaternion, Euler);
* :mod:`.seen` — which object a proximity sensor sees, and where;
* :mod:`.vision` — the served vision sensors' images, byte for byte;
* :mod:`.api` — the served ``sim.*`` functions, one module per group of CoppeliaSim's manual;
* :mod:`.simapi` — the dispatch table: the only ``sim.*`` functions a client can reach;
* :mod:`.clients` — per-client state and the stepping gate;
* :mod:`.socket_loop` — the ZeroMQ socket loop (:class:`RemoteApiServer`);
* :mod:`.view` — what a watcher reads of a served world (:class:`~.view.ServedView`).

The thesis's performance scenarios are the ``coppeliasim`` benchmark suite
(:mod:`puckboard.bench.coppeliasim`). Nothing here is imported by ``import puckboard``;
``zmq`` and ``cbor2`` load with :mod:`.socket_loop` and :mod:`.codec`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__all__ = ["RemoteApiServer", "serve_scene"]

if TYPE_CHECKING:  # pragma: no cover
    from .socket_loop import RemoteApiServer, serve_scene


def __getattr__(name: str) -> Any:
    if name in __all__:
        from . import socket_loop

        return getattr(socket_loop, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
