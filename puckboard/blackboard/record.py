"""The envelope every blackboard value travels in."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["Record"]


@dataclass(frozen=True, slots=True, init=False)
class Record:
    """An immutable, timestamped blackboard entry.

    ``stamp`` is the time the value describes, in the blackboard's clock (simulation time
    in a simulator, robot time on a real robot); ``received`` is the host's monotonic clock
    when the blackboard accepted it. ``seq`` counts writes to this key, starting at 1, so a
    reader can tell whether anything new arrived since it last looked.
    """

    key: str
    value: Any
    stamp: float
    received: float
    seq: int
    writer: str

    def __init__(
        self, key: str, value: Any, stamp: float, received: float, seq: int, writer: str
    ) -> None:
        # Every write makes one (16 a control cycle for two robots). A frozen dataclass's
        # own __init__ goes through object.__setattr__ field by field; setting the slots
        # through their descriptors does the same at about 60 % of the cost.
        _set_key(self, key)
        _set_value(self, value)
        _set_stamp(self, stamp)
        _set_received(self, received)
        _set_seq(self, seq)
        _set_writer(self, writer)

    def age(self, now: float) -> float:
        """How old the value is at ``now`` (same clock as ``stamp``)."""
        return now - self.stamp


_set_key, _set_value, _set_stamp, _set_received, _set_seq, _set_writer = (
    Record.__dict__[name].__set__ for name in ("key", "value", "stamp", "received", "seq", "writer")
)
