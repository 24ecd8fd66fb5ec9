"""Signals: ``sim.set/get/clear<String|Int32|Float>Signal``, three separate name spaces.

Signals are shared by every client (one controller can tell another, or a viewer, what
it does: an adapter publishes its robot's active layer as ``<model>.layer``) and cleared
when the simulation stops. The nine functions are alike but for the value's check, so one
factory makes each kind's three; the stores are the state's :class:`~.state.Signals`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..clients import ClientState
from .checks import Handler, Param, string

__all__ = ["signal_functions"]


def signal_functions(
    kind: str, store: dict[str, Any], check: Callable[[Any], Any]
) -> dict[str, tuple[Handler, tuple[Param, ...]]]:
    """``sim.set/get/clear<kind>Signal`` over one of :class:`Signals`' name spaces."""

    def set_signal(client: ClientState, name: str, value: Any) -> list[Any]:
        store[name] = value
        return []

    def get_signal(client: ClientState, name: str) -> list[Any]:
        return [store.get(name)]  # None when unset, as CoppeliaSim's nil

    def clear_signal(client: ClientState, name: str) -> list[Any]:
        """One signal, or every signal of the kind when ``name`` is empty (CoppeliaSim's
        ``sim.clear*Signal()`` without a name); returns how many were cleared."""
        if not name:
            count = len(store)
            store.clear()
            return [count]
        return [1 if store.pop(name, None) is not None else 0]

    name = Param("signalName", string)
    return {
        f"sim.set{kind}Signal": (set_signal, (name, Param("signalValue", check))),
        f"sim.get{kind}Signal": (get_signal, (name,)),
        f"sim.clear{kind}Signal": (clear_signal, (Param("signalName", string, ""),)),
    }
