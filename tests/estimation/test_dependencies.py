"""Knowledge sources and estimators stay on the layers' side of the architecture."""

from __future__ import annotations

import json
import subprocess
import sys


def _modules_after(statement: str) -> list[str]:
    code = f"import sys, json; {statement}; print(json.dumps(sorted(sys.modules)))"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    return json.loads(out.stdout)


def test_knowledge_imports_only_the_blackboard():
    mods = [
        m
        for m in _modules_after("import puckboard.estimation.knowledge")
        if m.startswith("puckboard")
    ]
    allowed = (
        "puckboard",
        "puckboard._lazy",  # how the package loads its names on first use
        "puckboard._version",
        "puckboard.estimation",
        "puckboard.estimation.knowledge",
        "puckboard.records",
    )
    assert all(m in allowed or m.startswith("puckboard.blackboard") for m in mods), mods


def test_estimation_knows_no_adapter_or_simulator_and_loads_filterpy_on_use():
    mods = _modules_after("import puckboard.estimation")
    assert not [m for m in mods if m.startswith(("puckboard.backends", "puckboard.sim"))]
    assert "filterpy" not in mods and "scipy" not in mods  # imported when a filter is built
