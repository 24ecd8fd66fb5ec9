"""Recordings on disk: the permissions of a saved file, and what a wrong file is called."""

from __future__ import annotations

import os
import stat
import sys

import numpy as np
import pytest
from viz_helpers import stand_in_recording

from puckboard.recording.recorder import load_recording


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX permission bits")
@pytest.mark.parametrize("umask", [0o022, 0o027])
def test_saved_recording_has_the_permissions_of_any_new_file(tmp_path, umask):
    rec = stand_in_recording(0.2)
    old = os.umask(umask)
    try:
        saved = rec.save(tmp_path / "run.npz")
        fresh = tmp_path / "fresh.txt"
        fresh.write_text("x", encoding="utf-8")
    finally:
        os.umask(old)
    assert stat.S_IMODE(saved.stat().st_mode) == stat.S_IMODE(fresh.stat().st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fresh.txt", "run.npz"]  # no .tmp


@pytest.mark.parametrize(
    ("name", "content"),
    [
        ("notes.txt", b"hello\n"),
        ("empty.npz", b""),
        ("broken.npz", b"PK\x03\x04 not really a zip"),
    ],
)
def test_a_file_that_is_not_a_recording_is_called_so_without_numpy_advice(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(ValueError, match="is not a puckboard recording") as info:
        load_recording(path)
    assert "pickle" not in str(info.value)


def test_a_single_array_file_is_not_a_recording(tmp_path):
    path = tmp_path / "array.npy"
    np.save(path, np.arange(3))
    with pytest.raises(ValueError, match="not a puckboard recording.*single NumPy array"):
        load_recording(path)
