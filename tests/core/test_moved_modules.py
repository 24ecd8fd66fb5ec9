"""Old import paths keep working for one release, warn, and are the very same modules."""

from __future__ import annotations

import importlib
import sys

import pytest

MOVED = {
    "puckboard.episode": "puckboard.control.episode",
    "puckboard.recording": "puckboard.viz.recording",
    "puckboard.knowledge": "puckboard.estimation.knowledge",
    "puckboard.sim.scene": "puckboard.scenario.scene",
    "puckboard.sim.scenefile": "puckboard.scenario.scenefile",
    "puckboard.sim.judge": "puckboard.scenario.judge",
    "puckboard.sim.ir": "puckboard.ir_response",
    "puckboard.behaviours.controllers": "puckboard.behaviours.presets",
}


@pytest.mark.parametrize(("old", "new"), sorted(MOVED.items()))
def test_old_path_warns_at_the_importing_line_and_is_the_new_module(old, new, monkeypatch):
    monkeypatch.delitem(sys.modules, old, raising=False)
    namespace: dict[str, object] = {}
    code = compile(f"import {old} as module", "student.py", "exec")
    with pytest.warns(DeprecationWarning, match=rf"{old} moved to {new}") as caught:
        exec(code, namespace)
    assert namespace["module"] is importlib.import_module(new)
    assert [w.filename for w in caught] == ["student.py"]


def test_scene_types_from_the_engine_package_warn_and_still_work():
    import puckboard.scenario as scenario
    import puckboard.sim as sim

    sim.__dict__.pop("Scene", None)
    with pytest.warns(DeprecationWarning, match="puckboard.sim.Scene moved to puckboard.scenario"):
        scene_type = sim.Scene
    assert scene_type is scenario.Scene
    with pytest.raises(AttributeError, match="has no attribute 'Nonesuch'"):
        _ = sim.Nonesuch
