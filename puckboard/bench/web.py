"""The web view under a class: does a room of browsers slow the simulation?

Runs the two-robot pass as fast as it goes (no pacing): without the web view, with it
and no browser, then with ``clients`` Server-Sent-Events streams open on the
loopback interface (held by a separate process, like real browsers, so their reading
does not count as the simulation's CPU time). Reports the simulation's real-time factor
both ways, the CPU seconds the simulating process spent per simulated second, and how
many frames each stream received per second.
"""

from __future__ import annotations

import subprocess
import sys
import time
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..control.episode import Episode

__all__ = ["run_suite"]

# A stand-in for a classroom of browsers: N threads each reading the event stream,
# counting frames. Each line on stdin asks for the counts so far; its end, for the last.
_READERS = r"""
import sys, threading, urllib.request
url, n = sys.argv[1], int(sys.argv[2])
counts = [0] * n
def read(k):
    try:
        with urllib.request.urlopen(url + "stream") as r:
            for line in r:
                if line.startswith(b"event: frame"):
                    counts[k] += 1
    except Exception:
        pass
for k in range(n):
    threading.Thread(target=read, args=(k,), daemon=True).start()
print("ready", flush=True)
for _ in sys.stdin:
    print(" ".join(map(str, counts)), flush=True)
print(" ".join(map(str, counts)), flush=True)
"""
#: How long the streams may take to deliver what the run sent them, on a loaded machine.
_DELIVERY_S = 10.0


def _delivered(readers: subprocess.Popen[str]) -> list[int]:
    """The readers' frame counts once every stream has had what the run sent it (each
    count above zero, or :data:`_DELIVERY_S` gone by): the frames a short run publishes
    may still be in flight when it returns, more so on a busy machine."""
    assert readers.stdin is not None and readers.stdout is not None
    deadline = time.monotonic() + _DELIVERY_S
    while True:
        readers.stdin.write("\n")
        readers.stdin.flush()
        counts = [int(v) for v in readers.stdout.readline().split()]
        if all(counts) or time.monotonic() > deadline:
            break
        time.sleep(0.02)
    out, _ = readers.communicate("", timeout=30)
    return [int(v) for v in out.split()]


def _timed_run(episode: Episode, duration: float) -> tuple[float, float]:
    """Wall and CPU seconds (this process, all its threads) of a full-length run."""
    wall0, cpu0 = time.perf_counter(), time.process_time()
    episode.run(duration, stop_early=False)
    return time.perf_counter() - wall0, time.process_time() - cpu0


def _bare_run(duration: float) -> dict[str, Any]:
    from ..control.episode import Episode

    wall, cpu = _timed_run(Episode("two-robot-pass", seed=0), duration)
    return {"realtime_factor": round(duration / wall, 1),
            "cpu_s_per_sim_s": round(cpu / duration, 4)}  # fmt: skip


def _one_run(duration: float, clients: int) -> dict[str, Any]:
    from ..control.episode import Episode
    from ..web import watch_episode

    episode = Episode("two-robot-pass", seed=0)
    view = watch_episode(episode, port=0, speed=None)
    readers = None
    try:
        if clients:
            readers = subprocess.Popen(
                [sys.executable, "-c", _READERS, view.url, str(clients)],
                stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
            )  # fmt: skip
            assert readers.stdout is not None
            readers.stdout.readline()
            deadline = time.monotonic() + 10.0
            while view.clients < clients and time.monotonic() < deadline:
                time.sleep(0.02)
        wall, cpu = _timed_run(episode, duration)
        frames: list[int] = []
        if readers is not None:
            frames = _delivered(readers)
        return {
            "connected": view.clients if clients else 0,
            "realtime_factor": round(duration / wall, 1),
            "cpu_s_per_sim_s": round(cpu / duration, 4),
            "frames_per_s_per_client": round(sum(frames) / max(1, len(frames)) / wall, 1)
            if frames else None,
        }  # fmt: skip
    finally:
        if readers is not None and readers.poll() is None:
            readers.kill()
        view.close()


def run_suite(steps: int | None = None, clients: int = 30) -> dict[str, Any]:
    """Real-time factor of a free-running two-robot pass with and without ``clients``
    streams; ``steps`` simulation steps per run (default 2400, two simulated minutes)."""
    steps = steps or 2400
    duration = steps * 0.05
    bare = _bare_run(duration)
    alone = _one_run(duration, 0)
    watched = _one_run(duration, clients)
    return {
        "sim_seconds": duration,
        "clients": clients,
        "without_web_view": bare,
        "without_clients": alone,
        "with_clients": watched,
        "slowdown": round(alone["realtime_factor"] / watched["realtime_factor"], 3),
    }
