"""The sweep's figure: rates in %, as the sensitivity figures show them."""

from __future__ import annotations

import pytest

from puckboard.sweep.rows import Outcome
from puckboard.sweep.summary import summarise


def test_the_sweep_figure_shows_rates_in_percent(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    import puckboard.sweep.plot as plot

    made, original = [], plot.new_figure

    def keep(**options):
        made.append(original(**options))
        return made[-1]

    monkeypatch.setattr(plot, "new_figure", keep)
    outcomes = [
        Outcome(f"k{gain}{s}", "stock", (("noise.proximity", gain),), s, s < 3 - 10 * gain, "",
                0.5, 0.0)
        for gain in (0.0, 0.1)
        for s in range(4)
    ]  # fmt: skip
    plot.plot_success(summarise(outcomes), "noise.proximity", tmp_path / "s.png")
    (ax,) = made[0].axes
    assert "%" in ax.get_ylabel()
    assert ax.get_ylim() == (-3, 103)
    (bars,) = ax.containers  # one line: the one controller
    assert list(bars.lines[0].get_ydata()) == [75.0, 50.0]
    assert (tmp_path / "s.png").read_bytes()[:4] == b"\x89PNG"
