"""Which processes descend from a process, and which of them still live.

With psutil where it is installed, else from /proc on Linux; elsewhere the tests that
need it are skipped. A process is identified by its id *and* its start time, so an id
reused by the system is not mistaken for a process left behind.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

try:
    import psutil
except ImportError:  # pragma: no cover - psutil comes with dask, our test extra
    psutil = None

PROC = Path("/proc")


def require_process_tree() -> None:
    """Skip the calling test where descendants cannot be listed."""
    if psutil is None and not (PROC / str(os.getpid()) / "stat").exists():
        pytest.skip("listing child processes needs psutil, or /proc (Linux)")


def _stat(pid: int) -> tuple[int, str, int] | None:
    """(parent id, state, start time) of ``pid`` from /proc, or None if it is gone."""
    try:
        text = (PROC / str(pid) / "stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2 :].split()  # the name may hold spaces
    return int(fields[1]), fields[0], int(fields[19])


def descendants(pid: int) -> set[tuple[int, float]]:
    """Every living descendant of ``pid`` as (id, start time)."""
    if psutil is not None:
        try:
            children = psutil.Process(pid).children(recursive=True)
        except psutil.NoSuchProcess:
            return set()
        found = set()
        for child in children:
            try:
                found.add((child.pid, child.create_time()))
            except psutil.NoSuchProcess:
                continue
        return found
    parents: dict[int, list[tuple[int, float]]] = {}
    for entry in PROC.iterdir():
        if entry.name.isdigit() and (stat := _stat(int(entry.name))) is not None:
            parents.setdefault(stat[0], []).append((int(entry.name), float(stat[2])))
    found, queue = set(), [pid]
    while queue:
        for child in parents.get(queue.pop(), []):
            found.add(child)
            queue.append(child[0])
    return found


def alive(process: tuple[int, float]) -> bool:
    """Whether this very process (same id, same start) still runs (zombies do not)."""
    pid, started = process
    if psutil is not None:
        try:
            proc = psutil.Process(pid)
            return proc.create_time() == started and proc.status() != psutil.STATUS_ZOMBIE
        except psutil.NoSuchProcess:
            return False
    stat = _stat(pid)
    return stat is not None and float(stat[2]) == started and stat[1] != "Z"


def command_line(pid: int) -> str:
    """The command line of ``pid`` ("" once it is gone)."""
    if psutil is not None:
        try:
            return " ".join(psutil.Process(pid).cmdline())
        except psutil.Error:
            return ""
    try:
        return (PROC / str(pid) / "cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return ""
