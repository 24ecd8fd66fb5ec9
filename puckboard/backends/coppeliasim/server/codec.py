"""Frames of the ZeroMQ remote API, protocol version 2: one CBOR map per message.

A request is ``{func, args, argsL, uuid}``; the first message of a client also carries
``ver``, ``lang`` and ``timeout``. A reply is ``{ret: [...]}``, ``{err: "..."}`` or, for
the stepping handshake, ``{func: "_*wait*_", args: []}``. This module turns bytes into a
validated :class:`Request` and replies into bytes, and nothing else: whatever a client
sends, decoding either yields a well-formed request or raises :class:`FrameError` with a
message that can go straight back to the client.

Both CBOR encoders the official client may use are accepted: ``cbor2`` (floats as
float64, numpy values converted) and the old ``cbor`` package (tuples as arrays).
Requests with an ``eval`` key (the real server's Lua escape hatch) are refused: this
server runs no code sent by a client.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import cbor2

__all__ = [
    "EXECUTED",
    "MAX_ARGS",
    "MAX_FRAME_BYTES",
    "WAIT",
    "FrameError",
    "Request",
    "decode_request",
    "encode_reply",
    "error_reply",
    "return_reply",
    "wait_reply",
]

#: Largest request we decode; ZeroMQ drops peers that send more (``MAXMSGSIZE``).
MAX_FRAME_BYTES = 1 << 20
#: Largest argument count (``argsL``) we pad to; no served function takes more than 8.
MAX_ARGS = 64
#: Longest function name we look up.
MAX_FUNC_NAME = 200

WAIT = "_*wait*_"
EXECUTED = "_*executed*_"
END = "_*end*_"

_VERSION_MISMATCH = "The client ZeroMQ remote API version does not match CoppeliaSim's version"


class FrameError(ValueError):
    """A message that is not a well-formed request; the text is sent back as ``err``."""

    def __init__(self, message: str, *, legacy: bool = False) -> None:
        super().__init__(message)
        #: Answer in the protocol-1 format too (``success``/``error``), for old clients.
        self.legacy = legacy


@dataclass(frozen=True)
class Request:
    """One decoded request.

    ``args`` is padded with ``None`` up to ``argsL``, as the real server does, so that
    trailing ``nil`` arguments survive. ``lang``/``ver``/``timeout`` are only present on
    a client's first message.
    """

    func: str
    args: list[Any]
    uuid: str
    lang: str | None = None
    ver: int | None = None
    timeout: float | None = None
    extra: dict[str, Any] = field(default_factory=dict)


def decode_request(raw: bytes) -> Request:
    """Decode and validate one request frame; :class:`FrameError` if it is not one."""
    if len(raw) > MAX_FRAME_BYTES:
        raise FrameError(f"message of {len(raw)} bytes is larger than {MAX_FRAME_BYTES}")
    if not raw:
        raise FrameError("empty message; expected a CBOR map {func, args, uuid}")
    try:
        msg = cbor2.loads(raw)
    except Exception as exc:  # CBORDecodeError, RecursionError, MemoryError, ValueError ...
        raise FrameError(f"message is not valid CBOR ({type(exc).__name__})") from None
    if not isinstance(msg, dict):
        raise FrameError(
            f"message is a CBOR {_type_name(msg)}; expected a map {{func, args, uuid}}"
        )
    if "eval" in msg:
        raise FrameError("'eval' requests are not served: this server runs no code from clients")
    uuid = msg.get("uuid")
    if uuid is None:
        # what CoppeliaSim answers a protocol-1 client (no uuid): say it in both formats
        raise FrameError(_VERSION_MISMATCH + " (the request has no 'uuid')", legacy=True)
    if not isinstance(uuid, str) or not 0 < len(uuid) <= 100:
        raise FrameError(f"'uuid' must be a short string, got {_type_name(uuid)}")
    func = msg.get("func")
    if not isinstance(func, str) or not func:
        raise FrameError(f"'func' must be a function name (string), got {_type_name(func)}")
    if len(func) > MAX_FUNC_NAME:
        raise FrameError(f"function name of {len(func)} characters is too long")
    args = msg.get("args", [])
    if args is None:
        args = []
    if not isinstance(args, list):
        raise FrameError(f"'args' of {func} must be an array, got {_type_name(args)}")
    if len(args) > MAX_ARGS:
        raise FrameError(f"{func} called with {len(args)} arguments; at most {MAX_ARGS}")
    args = list(args)
    count = msg.get("argsL")
    if isinstance(count, int) and not isinstance(count, bool) and len(args) < count <= MAX_ARGS:
        args.extend([None] * (count - len(args)))
    lang = msg.get("lang")
    ver = msg.get("ver")
    timeout = msg.get("timeout")
    return Request(
        func=func,
        args=args,
        uuid=uuid,
        lang=lang if isinstance(lang, str) else None,
        ver=ver if isinstance(ver, int) and not isinstance(ver, bool) else None,
        timeout=float(timeout)
        if isinstance(timeout, (int, float)) and not isinstance(timeout, bool) and timeout > 0
        else None,
    )


def encode_reply(reply: dict[str, Any]) -> bytes:
    """Encode a reply map (plain Python values only)."""
    return cbor2.dumps(reply)


def return_reply(values: list[Any] | tuple[Any, ...]) -> bytes:
    """``{ret: values}``: the client returns ``None``, the value, or a tuple of them."""
    return encode_reply({"ret": list(values)})


def error_reply(message: str, *, legacy: bool = False) -> bytes:
    """``{err: message}``; the client raises it as an exception."""
    reply: dict[str, Any] = {"err": message}
    if legacy:
        reply.update(success=False, error=message)
    return encode_reply(reply)


WAIT_REPLY = encode_reply({"func": WAIT, "args": []})


def wait_reply() -> bytes:
    """``{func: '_*wait*_'}``: the client answers ``_*executed*_`` and waits again."""
    return WAIT_REPLY


def _type_name(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "float"
    if isinstance(value, str):
        return "text string"
    if isinstance(value, (bytes, bytearray)):
        return "byte string"
    if isinstance(value, list):
        return "array"
    if isinstance(value, dict):
        return "map"
    return type(value).__name__
