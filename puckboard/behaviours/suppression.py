"""Timed suppression: a layer keeps control for a while after its trigger ends.

Brooks' suppressor nodes hold their output for a fixed time after the last input, so a
brief trigger produces a whole manoeuvre (back off for 0.5 s, say) instead of a twitch.
py_trees has no such decorator; :class:`HoldFor` is one. While the wrapped layer applies
it passes through; for ``duration`` seconds after it stops applying, the decorator keeps
the wheels and keeps asking the layer for its command.

Time comes from ``clock`` when given (tests inject one), else from the tick's frame, which
is simulation time in a simulator and the robot's clock on a real robot.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import py_trees
from py_trees.common import Status

from .context import TickContext, current_frame
from .layer import Layer, LayerNode, as_behaviour

__all__ = ["HoldFor"]


class HoldFor(py_trees.decorators.Decorator):
    """Keep ``layer`` in control for ``duration`` s after it last applied."""

    def __init__(
        self,
        layer: Layer,
        duration: float,
        *,
        clock: Callable[[], float] | None = None,
        name: str | None = None,
    ) -> None:
        if duration < 0:
            raise ValueError(f"HoldFor duration must be >= 0 seconds, got {duration}")
        node = as_behaviour(layer)  # refuses a class or a layer that skipped its __init__
        if not isinstance(node, LayerNode):
            raise TypeError(f"HoldFor wraps a Layer, got {type(layer).__name__}")
        super().__init__(name=name or f"HoldFor({layer.name}, {duration:g}s)", child=node)
        self.layer = layer
        self._node = node
        self.duration = duration
        self.clock = clock
        self.reads = layer.reads
        self.context: TickContext | None = None
        self._last_active: float | None = None

    def setup(self, **kwargs: Any) -> None:
        self.context = kwargs.get("context")

    def update(self) -> Status:
        context = self.context
        frame = current_frame(context, self.name)
        assert context is not None
        now = self.clock() if self.clock is not None else frame.time
        if self.decorated.status == Status.RUNNING:
            self._last_active = now
            return Status.RUNNING
        if self._last_active is not None and now - self._last_active < self.duration:
            layer = self.layer
            try:
                command = layer.command(self._node.frame)  # the layer's own frame
            except Exception as exc:
                error = context.blame(layer.name, exc)
                if error is None:
                    raise
                raise error from exc
            context.propose(layer.name, command)
            return Status.RUNNING
        self._last_active = None
        return Status.FAILURE

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID:  # pre-empted by a higher layer: forget the hold
            self._last_active = None
