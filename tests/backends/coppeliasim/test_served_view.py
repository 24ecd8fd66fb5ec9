"""The served world's read-only face (``RemoteApiServer.view()``), what the web view reads."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import puckboard
from puckboard.backends.coppeliasim.server.socket_loop import RemoteApiServer
from puckboard.scenario.scenefile import load_scene


@pytest.fixture
def server():  # not started: the view is read in the server's thread, here the test's
    srv = RemoteApiServer(load_scene("two-robot-pass"), host="127.0.0.1", port=0)
    yield srv
    srv.close()


def test_the_view_shows_the_served_world_and_follows_a_restore(server):
    view = server.view()
    assert view.world is server.api.world
    assert view.scene is server.api.world.scene
    assert view.model_names == tuple(b.name for b in server.api.objects.bases)
    assert len(view.model_names) == len(view.world.poses)
    server.api.reset()  # what sim.stopSimulation does: a new world, the scene restored
    assert view.world is server.api.world


def test_the_view_reads_signals_as_text_and_copies_the_targets(server):
    view = server.view()
    server.api.signals.string["ePuck#0.layer"] = b"cruise"
    server.api.signals.string["ePuck#1.layer"] = "line_follow"
    assert view.signal("ePuck#0.layer") == "cruise"
    assert view.signal("ePuck#1.layer") == "line_follow"
    assert view.signal("nobody.layer") is None
    targets = view.targets
    targets[:] = 9.0  # a watcher's copy: the served wheels are untouched
    assert np.all(server.api.targets == 0.0)


def test_the_view_lists_clients_without_handing_out_their_state(server):
    state, _ = server.clients.touch("0123456789abcdef", now=5.0)
    state.stepping = 2
    state.robots.add(1)
    (client,) = server.view().clients()
    assert (client.short, client.stepping, client.waiting, client.last_seen) == (
        "01234567",
        True,
        False,
        5.0,
    )
    assert client.robots == {1}
    state.parked = [b"envelope"]
    assert server.view().clients()[0].waiting
    with pytest.raises(AttributeError):
        client.stepping = False  # type: ignore[misc]


def test_the_web_view_reads_a_served_world_only_through_its_view():
    """No attribute path into the server's internals (the ``sim.*`` state, its signals,
    the object tree, a client's held reply) anywhere in web/."""
    web = Path(puckboard.__file__).parent / "web"
    offenders = [
        f"{p.name}:{node.lineno} .{node.attr}"
        for p in sorted(web.rglob("*.py"))
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8")))
        if isinstance(node, ast.Attribute)
        and node.attr in ("api", "signals", "objects", "bases", "parked")
    ]
    assert offenders == []
