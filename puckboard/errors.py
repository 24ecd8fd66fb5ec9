"""Exceptions that cross module boundaries; each message says what to do about it."""

from __future__ import annotations

__all__ = [
    "AdapterClosedError",
    "AdapterError",
    "ConnectionLostError",
    "NotSupportedError",
    "ProfileError",
    "PuckboardError",
    "SceneError",
]


class PuckboardError(Exception):
    """Base class of puckboard's own errors."""


class AdapterError(PuckboardError):
    """A robot adapter could not do what was asked."""


class NotSupportedError(AdapterError):
    """The backend cannot do this at all (a real robot cannot step, for example)."""


class AdapterClosedError(AdapterError):
    """The adapter was used after :meth:`close`."""


class ConnectionLostError(AdapterError):
    """The simulator or robot stopped answering within the timeout."""


class SceneError(PuckboardError, ValueError):
    """A scene file or scene description is invalid; the message names the field."""


class ProfileError(PuckboardError, ValueError):
    """A robot profile, a profile path or a value set on one is invalid; the message
    names the path (and the file), the value and what is allowed."""
