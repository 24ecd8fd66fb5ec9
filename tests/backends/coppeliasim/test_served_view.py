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
    world = server.api.world
    assert view.scene is world.scene
    assert view.model_names == tuple(b.name for b in server.api.objects.bases)
    first = view.step()
    as_read = first.poses.copy()
    assert len(view.model_names) == len(first.poses)
    assert (first.run, first.time, first.step_count) == (0, 0.0, 0)
    assert np.array_equal(first.poses, world.poses)
    assert np.array_equal(first.prox_distance, world.prox_distance)
    assert first.prox_range == tuple(p.prox_range for p in world.profiles)
    world.set_wheel_speeds(0, 3.0, 3.0)
    for _ in range(5):
        world.step()
    later = view.step()
    assert later.run == 0 and later.step_count == 5 and later.time > first.time
    assert not np.array_equal(later.poses[0], first.poses[0])
    assert np.array_equal(first.poses, as_read)  # the earlier step stayed as it was read
    server.api.reset()  # what sim.stopSimulation does: a new world, the scene restored
    restored = view.step()
    assert (restored.run, restored.step_count) == (1, 0)
    assert np.array_equal(restored.poses, first.poses)


def test_a_step_is_frozen_and_no_window_into_the_engine(server):
    step = server.view().step()
    world = server.api.world
    for name in ("poses", "collisions", "prox_distance", "ground", "wheel_speeds"):
        array = getattr(step, name)
        with pytest.raises(ValueError, match="read-only"):
            array[...] = 0
        assert not np.shares_memory(array, getattr(world, name)), name
    with pytest.raises(AttributeError):
        step.time = 1.0  # type: ignore[misc]
    assert not hasattr(server.view(), "world")


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
