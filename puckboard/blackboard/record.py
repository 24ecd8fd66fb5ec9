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


_new_record = object.__new__
_set_key, _set_value, _set_stamp, _set_received, _set_seq, _set_writer = (
    Record.__dict__[name].__set__ for name in ("key", "value", "stamp", "received", "seq", "writer")
)


def _record(key: str, value: Any, stamp: float, received: float, seq: int, writer: str) -> Record:
    """``Record(key, value, stamp, received, seq, writer)``, built in half the time.

    The blackboard makes several records per robot per control cycle. A frozen
    dataclass's ``__init__`` sets each field through ``object.__setattr__``; setting the
    slots through their descriptors does the same (``Record`` has no validation) with
    cheaper calls. Not part of the public API.
    """
    rec = _new_record(Record)
    _set_key(rec, key)
    _set_value(rec, value)
    _set_stamp(rec, stamp)
    _set_received(rec, received)
    _set_seq(rec, seq)
    _set_writer(rec, writer)
    return rec
