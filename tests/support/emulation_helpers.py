"""An emulated robot serving on a thread, shared by the tests that talk to it over a link."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from puckboard.control.emulation import Emulation


@contextmanager
def running_emulation(
    scene: Any, protocol: str, serial: str | None, *, seed: int, seconds: float
) -> Iterator[Emulation]:
    """Serve ``scene`` for at most ``seconds`` until the block ends.

    These tests are about the client, so the robot stays up whatever the client does
    (it does not stop when a client leaves or goes quiet).
    """
    em = Emulation(
        scene, protocol=protocol, serial=serial, seed=seed, until_client_leaves=False,
        idle_timeout=None,
    )  # fmt: skip
    thread = threading.Thread(target=em.run, args=(seconds,), daemon=True)
    thread.start()
    try:
        yield em
    finally:
        em.stop()
        thread.join(5)
        assert not thread.is_alive(), "the emulator did not stop"
