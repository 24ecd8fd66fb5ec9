"""The two methods, each in its own package with a public face in
``puckboard.sensitivity``, and the joint report's words taken from its constants."""

from __future__ import annotations

import ast
from pathlib import Path

from test_joint_profiles import _rows

import puckboard.sensitivity as sensitivity
from puckboard.sensitivity.joint import PROGRESS, analyse_rows
from puckboard.sensitivity.joint import report as joint_report


def test_both_methods_have_a_public_face():
    for name in ("sensitivity_plan", "run_sensitivity", "format_result", "plot_sensitivity",
                 "joint_plan", "run_joint", "from_rows", "format_joint", "plot_joint"):  # fmt: skip
        assert name in sensitivity.__all__ and callable(getattr(sensitivity, name)), name


def test_the_joint_method_borrows_nothing_private_of_one_at_a_time():
    joint = Path(sensitivity.__file__).parent / "joint"
    borrowed = []
    for path in joint.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and "one_at_a_time" in (node.module or ""):
                borrowed += [f"{path.name}: {a.name}" for a in node.names if a.name.startswith("_")]
                borrowed += [f"{path.name}: {node.module}" for _ in [0] if "plot" in node.module]
    assert borrowed == []


def test_ranked_by_progress_says_the_threshold_it_used(monkeypatch):
    params = {"robot.profile": "epuck", "variation": "plausible"}
    (a,) = analyse_rows(_rows(params), bins=2)  # 6 passes, 6 failures: too few for pass/fail
    assert a.ranked_by == PROGRESS
    monkeypatch.setattr(joint_report, "MIN_EVENTS", 7)
    text = joint_report.format_analysis(a, "robust")
    assert "ranked by progress (fewer than 7 passes or 7 failures" in text
