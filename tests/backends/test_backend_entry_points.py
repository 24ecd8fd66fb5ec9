"""A third-party package adds a backend through the ``puckboard.backends`` entry points."""

from __future__ import annotations

import logging
import sys

import pytest

from puckboard.backends import registry

MODULE = "puckboard_test_robot_backend"


@pytest.fixture
def installed(tmp_path, monkeypatch):
    """A fake installed distribution (a ``.dist-info`` on ``sys.path``) offering two
    backends: a new one, and one that tries to take a built-in name."""
    (tmp_path / f"{MODULE}.py").write_text(
        "def open_my_robot(*args, **options):\n    return ('my robot', args, options)\n",
        encoding="utf-8",
    )
    info = tmp_path / f"{MODULE}-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        "Metadata-Version: 2.1\nName: my-robot-backend\nVersion: 1.0\n", encoding="utf-8"
    )
    (info / "entry_points.txt").write_text(
        f"[{registry.ENTRY_POINT_GROUP}]\n"
        f"my-robot = {MODULE}:open_my_robot\n"
        f"embedded = {MODULE}:open_my_robot\n",
        encoding="utf-8",
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(registry, "BACKENDS", dict(registry.BACKENDS))
    monkeypatch.setattr(registry, "_installed_read", False)
    monkeypatch.delitem(sys.modules, MODULE, raising=False)
    return registry


def test_an_installed_backend_opens_by_its_name(installed):
    assert installed.open_backend("my-robot", 1, port=2) == ("my robot", (1,), {"port": 2})
    assert "my-robot" in installed.backend_names()


def test_an_installed_backend_may_be_the_default(installed, monkeypatch):
    monkeypatch.setenv(installed.BACKEND_ENV, "my-robot")
    assert installed.default_backend() == "my-robot"


def test_a_built_in_name_is_never_taken_by_an_installed_package(installed, caplog):
    builtin = installed.BACKENDS["embedded"]
    with caplog.at_level(logging.WARNING, logger=installed.__name__):
        names = installed.backend_names()
    assert installed.BACKENDS["embedded"] == builtin
    assert names.count("embedded") == 1
    assert "my-robot-backend offers a backend 'embedded'" in caplog.text


def test_an_unknown_name_lists_the_installed_backends_too(installed):
    with pytest.raises(ValueError, match=r"unknown backend 'nope'; known backends: .*my-robot"):
        installed.resolve_backend("nope")


def test_a_built_in_name_needs_no_look_at_the_installed_packages(installed, monkeypatch):
    def refuse(*_args, **_kwargs):
        raise AssertionError("the installed packages were read")

    monkeypatch.setattr("importlib.metadata.entry_points", refuse)
    assert installed.resolve_backend("fake") is not None
