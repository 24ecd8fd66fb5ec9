"""Exceptions that cross module boundaries; each message says what to do about it."""

from __future__ import annotations

__all__ = [
    "AdapterClosedError",
    "AdapterError",
    "CalibrationError",
    "ChallengeError",
    "ConnectionLostError",
    "LayerError",
    "NonFiniteError",
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


class CalibrationError(PuckboardError):
    """A step of a robot's calibration cannot work (no wall in front of it, wheels that do
    not turn, a sensor that does not respond ...); the message says what to fix."""


class ChallengeError(PuckboardError, ValueError):
    """A challenge file, a submission folder or a grading's output folder is not usable;
    the message names the file (and the table) and the fix."""


class SceneError(PuckboardError, ValueError):
    """A scene file or scene description is invalid; the message names the field."""


class ProfileError(PuckboardError, ValueError):
    """A robot profile, a profile setting name or a value set on one is invalid; the message
    names the path (and the file), the value and what is allowed."""


class NonFiniteError(PuckboardError, ValueError):
    """A record (a wheel command, a pose) was given something that is not a finite number:
    ``nan``, ``inf``, text. Caught where it is made, so the number never reaches a wheel."""


class LayerError(PuckboardError, ValueError):
    """A behaviour layer broke a rule puckboard checks for every layer: ``command()``
    returned something that is not a :class:`~puckboard.records.WheelCommand` of finite
    speeds, ``reads`` names a key the robot does not have, ``__init__`` skipped
    ``super().__init__()``. These are the controller's author's to fix, and the message
    says how; ``layer`` names the layer (``None`` for the controller as a whole).
    """

    def __init__(self, problem: str, layer: str | None = None) -> None:
        super().__init__(f"layer {layer!r}: {problem}" if layer is not None else problem)
        self.problem = problem
        self.layer = layer
