"""The envelope every blackboard value travels in."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["Record"]


@dataclass(frozen=True, slots=True)
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

    def age(self, now: float) -> float:
        """How old the value is at ``now`` (same clock as ``stamp``)."""
        return now - self.stamp
