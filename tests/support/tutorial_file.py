"""The tutorial's controller file, saved as the reader is told to, once per session.

``my_controller.py`` from the tutorial's block, plus the step 8 layer and factory (the
tutorial asks the reader to add them to the same file for the sweep). One file for the
whole session, at the same path in every worker process: an episode is cached under its
controller's spec (tests/support/episodes.py), so tests that run the reader's controller
on the same seeds share those episodes only when they name the same file.
"""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

from session_cache import ENV

__all__ = ["tutorial_controller_path"]

TUTORIAL = Path(__file__).resolve().parents[2] / "docs" / "tutorial.md"


def tutorial_controller_path() -> Path:
    """The file's path (written when this process first asks; the same text every time)."""
    page = TUTORIAL.read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```", page, re.MULTILINE | re.DOTALL)
    saved = [b for b in blocks if b.startswith("# my_controller.py\n")]
    assert len(saved) == 1, "the tutorial should have exactly one '# my_controller.py' block"
    (search,) = [b for b in blocks if "class FindLineWhereLastSeen(Layer)" in b]
    (factory,) = [b for b in blocks if "def remembering_controller():" in b]
    factory = factory[: factory.index("\n\nfor name")]
    text = "\n\n".join([saved[0], search, factory])
    session = os.environ.get(ENV)
    folder = Path(session if session else tempfile.mkdtemp(prefix="puckboard-")) / "student"
    folder.mkdir(exist_ok=True)
    path = folder / "my_controller.py"
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        partial = path.with_suffix(f".{os.getpid()}.part")
        partial.write_text(text, encoding="utf-8")
        partial.replace(path)  # atomic: another worker reads all of it or the old one
    return path
