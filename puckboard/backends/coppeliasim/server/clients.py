"""Who is connected, and when the simulation may advance (the stepping gate).

CoppeliaSim keeps one record per client, keyed on the ``uuid`` every request carries. A
client that called ``sim.setStepping(True)`` holds the simulation back: it advances one
step only when **every** stepping client has asked for that step with ``sim.step()``.
That is what lets several students' controllers, each in its own process, share one
synchronous simulation.

Clients never say goodbye (the Python client sends no ``_*end*_``), so absence is
inferred from silence, as CoppeliaSim's add-on does:

* the client's own ``timeout`` (sent with its first request; 600 s for the Python
  client), capped by ``max_idle``: after that it is forgotten and the wheels it
  commanded are stopped. Until then a silent stepping client (crashed, or sitting at a
  breakpoint) holds the simulation back, exactly as in CoppeliaSim;
* ``stepping_timeout`` (``None`` by default, CoppeliaSim's behaviour): when set, a
  stepping client silent for this long stops holding the others back until it speaks
  again — for a class, where one student's breakpoint should not freeze everybody.

A client that is waiting inside ``sim.step`` is never silent: the server holds its
``_*executed*_`` and answers it with a ``_*wait*_`` heartbeat now and then, and each new
``_*executed*_`` counts as a sign of life. A client that stops answering the heartbeat
is treated like any other silent client.

What each client last did, and how many of its ``sim.step`` calls came while the
simulation was not running, is kept so that the server can say *who* holds a class back
and why (a loop that began before the simulation started ends early, and its client
leaves while still stepping).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = ["ClientState", "ClientTable"]


@dataclass
class ClientState:
    """What the server remembers about one client (one ``uuid``)."""

    uuid: str
    lang: str = "?"
    idle_timeout: float = 600.0
    first_seen: float = 0.0
    last_seen: float = 0.0
    calls: int = 0
    #: ``sim.setStepping`` nesting level; > 0 means the client gates the simulation.
    stepping: int = 0
    #: Step number this client waits for (valid while ``waiting``).
    desired_step: int = 0
    #: Inside ``sim.step``: waiting for the simulation to reach ``desired_step``.
    waiting: bool = False
    #: ZeroMQ envelope of a held ``_*executed*_`` (answered when the step is done).
    parked: Any = None
    parked_since: float = 0.0
    #: The step was done before the client's ``_*executed*_`` arrived: answer that at once.
    released: bool = False
    #: Robots whose wheels this client commanded (stopped when it is forgotten).
    robots: set[int] = field(default_factory=set)
    #: The last ``sim.*`` function it called, and when.
    last_call: str = ""
    last_call_at: float = 0.0
    #: Its ``sim.step`` calls, and how many came while the simulation was not running.
    steps: int = 0
    idle_steps: int = 0
    #: When its pending ``sim.step`` began (valid while ``waiting``).
    wait_since: float = 0.0
    #: Warnings the server gives once per client: it stepped while the simulation was
    #: not running; it held the other stepping clients back.
    warned_idle_step: bool = False
    warned_holding: bool = False

    @property
    def short(self) -> str:
        return self.uuid[:8]


class ClientTable:
    """All known clients and the stepping gate; see the module docstring."""

    def __init__(self, *, stepping_timeout: float | None = None, max_idle: float = 600.0) -> None:
        if (stepping_timeout is not None and stepping_timeout <= 0) or max_idle <= 0:
            raise ValueError("stepping_timeout and max_idle must be positive seconds")
        self.stepping_timeout = stepping_timeout
        self.max_idle = max_idle
        self._clients: dict[str, ClientState] = {}

    def __len__(self) -> int:
        return len(self._clients)

    def __iter__(self):  # type: ignore[no-untyped-def]
        return iter(list(self._clients.values()))

    def get(self, uuid: str) -> ClientState | None:
        return self._clients.get(uuid)

    def touch(
        self, uuid: str, now: float, *, lang: str | None = None, timeout: float | None = None
    ) -> tuple[ClientState, bool]:
        """The client's record (created on first contact); returns ``(state, is_new)``."""
        state = self._clients.get(uuid)
        new = state is None
        if state is None:
            state = ClientState(uuid=uuid, first_seen=now, idle_timeout=self.max_idle)
            self._clients[uuid] = state
        if lang is not None:
            state.lang = lang
        if timeout is not None:
            state.idle_timeout = min(timeout, self.max_idle)
        state.last_seen = now
        state.calls += 1
        return state, new

    def forget(self, uuid: str) -> ClientState | None:
        return self._clients.pop(uuid, None)

    def gating(self, now: float) -> list[ClientState]:
        """Stepping clients that currently hold the simulation back."""
        return [
            c
            for c in self._clients.values()
            if c.stepping > 0
            and (
                c.parked is not None
                or self.stepping_timeout is None
                or now - c.last_seen <= self.stepping_timeout
            )
        ]

    def gate_open(self, step: int, now: float) -> bool:
        """True when some client steps and every gating client asked for step ``step+1``."""
        gating = self.gating(now)
        return bool(gating) and all(c.waiting and c.desired_step > step for c in gating)

    def done_waiting(self, step: int) -> list[ClientState]:
        """Clients whose requested step has been reached (they get their reply now)."""
        return [c for c in self._clients.values() if c.waiting and c.desired_step <= step]

    def expired(self, now: float) -> list[ClientState]:
        """Forget (and return) clients silent for longer than their idle timeout."""
        gone = [
            c
            for c in self._clients.values()
            if c.parked is None and now - c.last_seen > c.idle_timeout
        ]
        for c in gone:
            del self._clients[c.uuid]
        return gone

    def reset_stepping(self) -> list[ClientState]:
        """``sim.stopSimulation``: nobody steps any more; returns the clients that waited."""
        released = []
        for c in self._clients.values():
            c.stepping = 0
            if c.waiting:
                released.append(c)
        return released
