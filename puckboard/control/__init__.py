"""The control loop that ties adapters, the blackboard and controllers together."""

from .loop import Binding, ControlLoop

__all__ = ["Binding", "ControlLoop"]
