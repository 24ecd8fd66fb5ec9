"""The ``transfer`` benchmark suite: registered, and its flagship is the page's."""

from __future__ import annotations

from puckboard import bench
from puckboard.behaviours import load_controller
from puckboard.bench import transfer


def test_the_suite_is_registered_and_resolves():
    assert bench.resolve_suite("transfer") is transfer.run_suite


def test_the_student_s_controller_is_the_tutorial_s_block_and_loads(tmp_path):
    """Kept in the package (the documents are not installed), equal to the page's block."""
    import re
    from pathlib import Path

    from puckboard.bench.tutorial_controller import SOURCE

    page = Path(__file__).resolve().parents[2] / "docs" / "tutorial.md"
    blocks = re.findall(
        r"^```python\n(# my_controller\.py\n.*?)^```", page.read_text(encoding="utf-8"), re.M | re.S
    )
    assert blocks == [SOURCE]
    spec = transfer.student_controller(tmp_path)
    assert spec == f"{tmp_path / 'my_controller.py'}:my_controller"
    saved = (tmp_path / "my_controller.py").read_text(encoding="utf-8")
    assert saved.startswith("# my_controller.py\n")
    assert load_controller(spec).layers  # a controller with layers, as the tutorial builds


def test_the_flagship_is_three_controllers_two_profiles_two_scenes(tmp_path):
    plan, scenes = transfer.flagship_plan(1, tmp_path)
    assert len(plan.controllers) == 3
    assert plan.scenes == transfer.FLAGSHIP_SCENES
    assert all(p == transfer.FLAGSHIP_PROFILES for p in plan.profiles.values())
    assert {s.scenario for s in plan.sweeps} <= set(scenes)
