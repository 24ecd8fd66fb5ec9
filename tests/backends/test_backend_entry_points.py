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
        "from puckboard.backends.embedded import open_embedded\n"
        "from puckboard.backends.registry import with_abilities\n\n"
        "def open_my_robot(*args, **options):\n    return ('my robot', args, options)\n\n"
        "@with_abilities(calibratable=True, remote=True)\n"
        "def open_my_epuck(*args, **options):\n    return ('my e-puck', args, options)\n\n"
        "@with_abilities(simulated=True, link_timing=True)\n"
        "def open_my_simulator(scene, **options):\n    return open_embedded(scene, **options)\n\n"
        "def open_plain_simulator(scene, **options):\n    return open_embedded(scene, **options)\n",
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
        f"my-epuck = {MODULE}:open_my_epuck\n"
        f"my-simulator = {MODULE}:open_my_simulator\n"
        f"plain-simulator = {MODULE}:open_plain_simulator\n"
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


# -- what a backend can do is asked of it, never read off its name -------------------------
def test_a_built_in_backend_says_what_it_can_do_without_being_imported(installed, monkeypatch):
    def refuse(*_args, **_kwargs):
        raise AssertionError("a backend was imported to ask what it can do")

    monkeypatch.setattr("pkgutil.resolve_name", refuse)
    monkeypatch.setattr("importlib.metadata.entry_points", refuse)
    embedded = installed.abilities_of("embedded")
    assert (embedded.simulated, embedded.link_timing, embedded.remote) == (True, True, False)
    assert installed.abilities_of("sercom").calibratable
    assert not installed.abilities_of("coppeliasim").calibratable


def test_an_installed_backend_says_what_it_can_do_through_its_factory(installed):
    assert installed.abilities_of("my-epuck") == installed.BackendAbilities(
        calibratable=True, remote=True
    )
    assert installed.abilities_of("my-robot") == installed.BackendAbilities()  # said nothing
    assert installed.backend_names(lambda able: able.calibratable) == [
        "epuck2-wifi", "my-epuck", "sercom"
    ]  # fmt: skip
    with pytest.raises(ValueError, match="unknown backend 'nope'"):
        installed.abilities_of("nope")


def test_a_misspelt_ability_is_refused_where_it_is_declared(installed):
    with pytest.raises(TypeError, match="link_timeing"):
        installed.with_abilities(link_timeing=True)


def test_an_installed_simulator_that_simulates_the_link_runs_at_a_profiles_link(
    installed, tmp_path
):
    """The profile's measured link is taken by the backend that says it simulates the
    link, whatever its name, and by no other."""
    from puckboard.control.episode import Episode
    from puckboard.profile import load_profile_file
    from puckboard.scenario import load_scene

    path = tmp_path / "mine.toml"
    path.write_text('base = "epuck"\n\n[link]\nperiod = 0.1\nlatency = 0.05\n', "utf-8")
    scene = load_scene("line-follow").with_profile(load_profile_file(path))
    timed = Episode(scene, backend="my-simulator")
    plain = Episode(scene, backend="plain-simulator")
    for episode in (timed, plain):
        episode.connection.close()
    assert (timed.loop.period, timed.scene.control.latency) == pytest.approx((0.1, 0.05))
    assert plain.scene.control == scene.control and plain.loop.period != pytest.approx(0.1)


def test_calibrate_drives_an_installed_backend_that_says_it_can_be_calibrated(installed):
    import argparse

    from puckboard.cli import calibrate
    from puckboard.cli.errors import CliError

    def options(backend):
        args = argparse.Namespace(backend=backend, what="ir", host="10.0.0.9", port=None)
        args.device = None
        return calibrate._backend_options(args)

    assert options("my-epuck") == {"host": "10.0.0.9"}
    for backend in ("my-robot", "my-simulator", "embedded"):
        with pytest.raises(CliError, match=f"--backend {backend}: calibrate ir drives a real"):
            options(backend)
