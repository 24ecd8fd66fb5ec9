"""A class of stepping clients on one served simulation: the early-starter trap.

``sim.step`` returns at once while the simulation is stopped, as in CoppeliaSim. A
client whose loop begins before somebody starts the simulation therefore runs ahead,
ends early and leaves while still stepping, and every other client waits for it until
its idle timeout. The server keeps those semantics but says so in its log: once per
client when a stepping client steps a stopped simulation, and once per client when the
others have waited for it too long, naming it. The loop docs/coppeliasim.md recommends
(clients/class_member.py, quoted verbatim there) neither runs ahead nor freezes anybody.
"""

from __future__ import annotations

import json
import logging
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import zmq
from coppeliasim_support import start_server, stop_server
from coppeliasim_zmqremoteapi_client import RemoteAPIClient

pytestmark = pytest.mark.network

CLIENTS = Path(__file__).parent / "clients"
DOCS = Path(__file__).parents[3] / "docs" / "coppeliasim.md"
SERVER_LOG = "puckboard.backends.coppeliasim.server"
STOPPED_STEP = "called sim.step while the simulation is stopped"
HELD_BACK = "in sim.step for client"


def _client(port: int) -> RemoteAPIClient:
    client = RemoteAPIClient("127.0.0.1", port)
    client.socket.setsockopt(zmq.RCVTIMEO, 5000)
    client.socket.setsockopt(zmq.LINGER, 0)
    return client


def _warnings(caplog: pytest.LogCaptureFixture, text: str) -> list[str]:
    return [
        r.getMessage()
        for r in caplog.records
        if r.levelno == logging.WARNING and text in r.getMessage()
    ]


def test_a_client_stepping_before_the_start_is_named_when_it_holds_the_others_back(caplog):
    caplog.set_level(logging.WARNING, logger=SERVER_LOG)
    srv = start_server(stall_warning=0.3, realtime=False)
    early, starter, lecturer = (_client(srv.port) for _ in range(3))
    try:
        sim_e, sim_s, sim_l = (c.require("sim") for c in (early, starter, lecturer))
        # the early client's loop begins before anybody started the simulation
        sim_e.setStepping(True)
        for _ in range(5):
            sim_e.step()  # returns at once: there is no step to wait for
        assert srv.api.world.step_count == 0
        early.socket.close(0)  # its loop is over: it leaves, still in stepping mode
        # the starter starts the simulation and steps: it waits for the early client
        sim_s.setStepping(True)
        sim_s.startSimulation()
        done = threading.Event()
        thread = threading.Thread(target=lambda: (sim_s.step(), done.set()), daemon=True)
        thread.start()
        assert not done.wait(1.0)  # frozen: what a class saw for 600 s
        deadline = time.monotonic() + 5.0
        while not _warnings(caplog, HELD_BACK) and time.monotonic() < deadline:
            time.sleep(0.05)
        sim_l.stopSimulation()  # releases the waiting starter
        assert done.wait(5.0)
        thread.join(5.0)
    finally:
        for c in (starter, lecturer):
            c.socket.close(0)
        stop_server(srv)

    who = early.uuid[:8]
    stopped = _warnings(caplog, STOPPED_STEP)
    assert len(stopped) == 1, stopped  # once, though it stepped five times
    assert f"client {who} " in stopped[0]
    assert "sim.getSimulationState()" in stopped[0]
    held = _warnings(caplog, HELD_BACK)
    assert len(held) == 1, held  # the starter never left sim.step: it is not named
    assert f"for client {who}," in held[0]
    assert "its last call was sim.step" in held[0]
    assert "(5 sim.step calls, 5 of them while the simulation was not running)" in held[0]
    assert "--stepping-timeout" in held[0]
    assert starter.uuid[:8] not in " ".join(stopped + held)


def _observe_steppers(srv, count: int) -> threading.Event:
    """An event set, from the server's own thread, once ``count`` clients step."""
    ready = threading.Event()

    def observe(server) -> None:
        if sum(1 for c in server.clients if c.stepping > 0) >= count:
            ready.set()

    srv.add_step_observer(observe)
    return ready


def test_the_documented_class_loop_waits_for_the_start_and_frees_the_others(caplog):
    """Three class members run the documented loop; the simulation is started late, and
    one member does fewer steps and leaves: nobody runs ahead and nobody freezes."""
    caplog.set_level(logging.WARNING, logger=SERVER_LOG)
    srv = start_server(realtime=False)  # nothing advances unless the members step it
    steps = [8, 20, 20]
    members: list[subprocess.Popen[str]] = []
    try:
        ready = _observe_steppers(srv, len(steps))
        script = str(CLIENTS / "class_member.py")
        members = [
            subprocess.Popen(
                [sys.executable, script, "127.0.0.1", str(srv.port), str(n)],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
            )
            for n in steps
        ]
        assert ready.wait(60.0), "the members never reached stepping mode"
        time.sleep(0.3)  # they poll sim.getSimulationState(); nobody steps yet
        assert srv.api.world.step_count == 0
        lecturer = _client(srv.port)
        try:
            sim = lecturer.require("sim")
            sim.startSimulation()
            dt = sim.getSimulationTimeStep()
            outs = [m.communicate(timeout=60) for m in members]
        finally:
            lecturer.socket.close(0)
    finally:
        for m in members:
            if m.poll() is None:
                m.kill()
                m.wait()
        stop_server(srv)
    for m, (_, err) in zip(members, outs):
        assert m.returncode == 0, err
    times = [json.loads(out.strip().splitlines()[-1])["time"] for out, _ in outs]
    # the two long loops ran in lockstep from the first step to the last
    assert times[1] == pytest.approx(20 * dt) and times[2] == pytest.approx(20 * dt)
    assert 8 * dt - 1e-9 <= times[0] <= 20 * dt + 1e-9
    assert srv.api.world.step_count == 20  # nobody stepped alone, nobody stepped twice
    assert not _warnings(caplog, STOPPED_STEP)


def test_the_docs_quote_the_class_loop_verbatim():
    script = (CLIENTS / "class_member.py").read_text(encoding="utf-8")
    loop = script.split("# -- the class loop --\n", 1)[1].split("# -- end of the class loop", 1)[0]
    docs = DOCS.read_text(encoding="utf-8")
    section = docs.split("### A class of stepping clients", 1)[1].split("\n## ", 1)[0]
    assert f"```python\n{loop}```" in section
