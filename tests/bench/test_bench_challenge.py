"""The ``challenge`` benchmark suite: registered, and its class is what it says."""

from __future__ import annotations

from puckboard import bench
from puckboard.bench import challenge
from puckboard.challenge.submissions import find_submissions


def test_the_suite_is_registered_and_resolves():
    assert bench.resolve_suite("challenge") is challenge.run_suite


def test_the_class_is_distinct_files_of_the_shipped_controllers_and_the_tutorial_s(tmp_path):
    kinds = challenge.make_class(8, tmp_path / "class")
    assert kinds[:4] == ["robust", "improved", "stock", "tutorial"]
    found = find_submissions(tmp_path / "class")
    assert len(found) == 8 and len({s.digest for s in found}) == 8  # each a version of its own
    namespace: dict[str, object] = {}
    exec((tmp_path / "class" / "student_03.py").read_text(), namespace)
    assert callable(namespace["make_controller"])
