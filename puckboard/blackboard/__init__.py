"""A thread-safe blackboard of timestamped, immutable records.

This package imports nothing else of puckboard: it is the one piece every other part
may depend on.
"""

from .record import Record
from .schema import ArraySchema, InstanceOf, NumberSchema, Schema
from .store import (
    Blackboard,
    MissingValueError,
    Namespace,
    Snapshot,
    StaleValueError,
    Subscription,
)

__all__ = [
    "ArraySchema",
    "Blackboard",
    "InstanceOf",
    "MissingValueError",
    "Namespace",
    "NumberSchema",
    "Record",
    "Schema",
    "Snapshot",
    "StaleValueError",
    "Subscription",
]
