"""Files a reader never sees half-written: written beside their place, then moved in.

A recording shared with a class, or a replay page on a course site, is either the old
file or the new one, never a torn one, even when the writer is interrupted.
"""

from __future__ import annotations

import os
import secrets
from pathlib import Path

__all__ = ["create_beside", "write_atomically"]


def create_beside(path: Path) -> tuple[int, Path]:
    """A new, empty temporary file in ``path``'s directory, open for writing.

    It is created with mode ``0o666`` so that the umask (and a directory's default ACL)
    set its permissions, as for any other file the user writes, such as the GIF or MP4
    of the same run. :func:`tempfile.mkstemp` would make it ``0o600``, and
    :func:`os.replace` keeps the temporary file's mode, so a recording shared with a
    class could not be read by it. ``O_EXCL`` with a random name keeps mkstemp's
    guarantee that no existing file is opened by mistake.
    """
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):
        tmp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
        try:
            return os.open(tmp, flags, 0o666), tmp
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary file name next to {str(path)!r}")


def write_atomically(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file beside it; returns ``path``."""
    fd, tmp = create_beside(path)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
