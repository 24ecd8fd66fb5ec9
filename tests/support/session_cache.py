"""Results computed once per test session, shared by the session's worker processes.

The suite runs in several processes (pytest-xdist, see tests/conftest.py), and a result
kept in one process's memory is computed again by the next process that asks for it. A
result kept here is computed by whichever process asks first and read back, as a pickle,
by the others; a process that asks while another computes it waits for that one.

The folder is the session's own (tests/conftest.py creates it and names it in
``PUCKBOARD_TEST_CACHE``, which the workers inherit) and is removed when the session
ends, so nothing outlives a run: an edit to the code is always measured afresh.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import time
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

__all__ = ["ENV", "once"]

#: The environment variable naming the session's folder.
ENV = "PUCKBOARD_TEST_CACHE"
#: How long a process waits for another to finish a result before computing it itself
#: (as when that process was killed half-way): far longer than any one result takes.
PATIENCE_S = 600.0

T = TypeVar("T")


def once(key: str, compute: Callable[[], T]) -> T:
    """``compute()``, computed once per session under ``key`` (``repr`` of its inputs)."""
    folder = os.environ.get(ENV)
    if not folder or not Path(folder).is_dir():  # run without tests/conftest.py
        return compute()
    name = hashlib.sha256(key.encode()).hexdigest()[:32]
    done = Path(folder) / f"{name}.pickle"
    lock = Path(folder) / f"{name}.lock"
    deadline = time.monotonic() + PATIENCE_S
    while not done.exists():
        try:
            handle = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:  # another process computes it
            if time.monotonic() > deadline:
                return compute()
            time.sleep(0.02)
            continue
        try:
            if done.exists():  # finished between the check and the lock
                break
            result = compute()
            partial = done.with_suffix(f".{os.getpid()}.part")
            partial.write_bytes(pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL))
            partial.replace(done)  # atomic: a reader sees all of it or nothing
            return result
        finally:
            os.close(handle)
            lock.unlink()
    return pickle.loads(done.read_bytes())  # type: ignore[no-any-return]
