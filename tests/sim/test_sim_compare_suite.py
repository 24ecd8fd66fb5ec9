"""The ``compare`` benchmark suite (puckboard's engine next to IR-SIM) skips cleanly
without IR-SIM, and its puckboard side runs."""

from __future__ import annotations

import sys

from puckboard import bench
from puckboard.bench import compare


def test_compare_is_skipped_with_a_note_when_irsim_is_missing(monkeypatch):
    monkeypatch.setitem(sys.modules, "irsim", None)  # import irsim raises ImportError
    result = bench.run_suites(["compare"], steps=5)["suites"]["compare"]
    assert "skipped" in result
    assert "pip install 'puckboard[compare]'" in result["skipped"]


def test_the_puckboard_side_of_the_comparison_runs():
    rate, near = compare._puckboard_rate(30)
    assert rate > 0
    assert 0.0 <= near <= 1.0
