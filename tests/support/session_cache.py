"""Results computed once per test session, shared by the session's worker processes.

The suite runs in several processes (pytest-xdist, see tests/conftest.py), and a result
kept in one process's memory is computed again by the next process that asks for it. A
result kept here is computed by whichever process asks first and read back, as a pickle,
by the others.

A process that needs a result another process is computing does not sit idle: asked for
several results at once (:func:`each`), it computes the ones nobody has started and reads
the others back at the end, so two processes that want the same ten episodes share them
five and five instead of one waiting for the other's ten.

The folder is the session's own (tests/conftest.py creates it and names it in
``PUCKBOARD_TEST_CACHE``, which the workers inherit) and is removed when the session
ends, so nothing outlives a run: an edit to the code is always measured afresh.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TypeVar

__all__ = ["ENV", "each", "once"]

#: The environment variable naming the session's folder.
ENV = "PUCKBOARD_TEST_CACHE"
#: How long a process waits for another to finish a result before computing it itself
#: (as when that process was killed half-way): far longer than any one result takes.
PATIENCE_S = 600.0

T = TypeVar("T")
_BUSY = object()  # another process holds the result's lock


def once(key: str, compute: Callable[[], T]) -> T:
    """``compute()``, computed once per session under ``key`` (``repr`` of its inputs)."""
    return each([key], lambda _: compute())[0]


def each(keys: Sequence[str], compute: Callable[[int], T]) -> list[T]:
    """``compute(i)`` for each of ``keys``, each computed once per session.

    Results another process is computing are read back after this one has computed every
    result nobody had started."""
    folder = os.environ.get(ENV)
    if not folder or not Path(folder).is_dir():  # run without tests/conftest.py
        return [compute(i) for i in range(len(keys))]
    results: dict[int, T] = {}
    deadline = time.monotonic() + PATIENCE_S
    pending = list(range(len(keys)))
    while pending:
        busy = []
        for i in pending:
            got = _attempt(Path(folder), keys[i], lambda i=i: compute(i))
            if got is _BUSY:
                busy.append(i)
            else:
                results[i] = got  # type: ignore[assignment]
        if busy and len(busy) == len(pending):  # nothing left to do but wait
            if time.monotonic() > deadline:  # its process died: compute them here
                results.update((i, compute(i)) for i in busy)
                break
            time.sleep(0.02)
        pending = busy
    return [results[i] for i in range(len(keys))]


def _attempt(folder: Path, key: str, compute: Callable[[], T]) -> T | object:
    """The result under ``key``, computed here when nobody has; ``_BUSY`` while another
    process computes it."""
    name = hashlib.sha256(key.encode()).hexdigest()[:32]
    done = folder / f"{name}.pickle"
    if done.exists():
        return pickle.loads(done.read_bytes())
    lock = folder / f"{name}.lock"
    try:
        handle = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return _BUSY
    try:
        if done.exists():  # finished between the check and the lock
            return pickle.loads(done.read_bytes())
        result = compute()
        partial = done.with_suffix(f".{os.getpid()}.part")
        partial.write_bytes(pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL))
        partial.replace(done)  # atomic: a reader sees all of it or nothing
        return result
    finally:
        os.close(handle)
        lock.unlink()
