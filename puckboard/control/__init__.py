"""The control loop that ties adapters, the blackboard and controllers together."""

from .loop import Binding, ControlLoop, bind

__all__ = ["Binding", "ControlLoop", "bind"]
