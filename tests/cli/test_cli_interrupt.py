"""Ctrl-C ends every command with status 130, the servers and web views included,
which ended with 0 as if they had finished (issue 30, round 4, item 14)."""

from __future__ import annotations

import pytest

from puckboard.cli import main


def ctrl_c(*_args: object, **_kwargs: object) -> None:
    raise KeyboardInterrupt


def test_serve_ends_with_130_on_ctrl_c_after_its_summary(monkeypatch, capsys):
    pytest.importorskip("zmq")
    from puckboard.backends.coppeliasim.server import socket_loop

    monkeypatch.setattr(socket_loop.RemoteApiServer, "serve_forever", ctrl_c)
    assert main(["serve", "--port", "0"]) == 130
    captured = capsys.readouterr()
    assert "server stopped after 0 requests" in captured.out
    assert captured.err.strip().splitlines()[-1] == "puckboard serve: interrupted"


def test_a_web_view_kept_up_ends_with_130_on_ctrl_c(monkeypatch, tmp_path, capsys):
    import time

    pytest.importorskip("aiohttp")
    run = tmp_path / "r.npz"
    assert main(["run", "line-follow", "--duration", "0.3", "--record", str(run), "--json"]) == 0
    monkeypatch.setattr(time, "sleep", ctrl_c)  # the wait for Ctrl-C gets it at once
    assert main(["replay", str(run), "--web", "--web-port", "0"]) == 130
    assert capsys.readouterr().err.strip().splitlines()[-1] == "puckboard replay: interrupted"
