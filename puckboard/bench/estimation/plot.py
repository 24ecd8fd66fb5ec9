"""The estimation plot: an estimate against the truth, with its covariance ellipses.

A reader judges an estimate by whether its error stays inside what it claims (its 2σ),
not only by the error's size; the figure shows both, path and error over time, one
column per trace. matplotlib is imported only when a figure is drawn.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...viz.figures import new_figure

if TYPE_CHECKING:
    from .trial import Trace

__all__ = ["plot_traces"]


def plot_traces(
    traces: Sequence[Trace], path: str | Path, *, every: float = 30.0, title: str = ""
) -> Path:
    """Estimated against true paths, with 2σ position ellipses every ``every`` s (top), and
    the position error over time against the estimate's own 2σ (bottom).

    One column per trace. matplotlib is imported here (the ``viz`` extra); the figure is
    written to ``path`` (its suffix picks the format).
    """
    from matplotlib.patches import Ellipse

    n = len(traces)
    fig = new_figure(figsize=(5.0 * n, 7.2))
    axes = fig.subplots(2, n, squeeze=False, gridspec_kw={"height_ratios": [3, 1.4]})
    for col, trace in enumerate(traces):
        ax, ax_err = axes[0][col], axes[1][col]
        truth = np.array(trace.truth)
        est = np.array(trace.est)
        t = np.array(trace.t)
        ax.plot(truth[:, 0], truth[:, 1], color="black", lw=1.2, label="truth (simulator)")
        ax.plot(est[:, 0], est[:, 1], color="tab:red", lw=0.9, ls="--", label="estimate")
        next_t = every
        for k, tk in enumerate(t):
            if tk + 1e-9 < next_t:
                continue
            next_t = tk + every
            vals, vecs = np.linalg.eigh(trace.cov[k])
            vals = np.clip(vals, 0.0, None)
            angle = math.degrees(math.atan2(vecs[1, 1], vecs[0, 1]))
            ax.add_patch(
                Ellipse(
                    (est[k, 0], est[k, 1]),
                    width=4 * math.sqrt(vals[1]),
                    height=4 * math.sqrt(vals[0]),
                    angle=angle,
                    fill=False,
                    color="tab:blue",
                    lw=0.8,
                )
            )
            ax.plot(est[k, 0], est[k, 1], ".", color="tab:red", ms=3)
            ax.plot(truth[k, 0], truth[k, 1], ".", color="black", ms=3)
        m = trace.metrics()
        ax.set_title(
            f"{trace.robot}: {trace.variant}\n"
            f"final error {m['final_position_error_m'] * 100:.1f} cm, "
            f"{m['final_heading_error_deg']:.1f}° after {m['distance_m']:.1f} m",
            fontsize=9,
        )
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.grid(True, lw=0.3)
        error = np.hypot(est[:, 0] - truth[:, 0], est[:, 1] - truth[:, 1])
        two_sd = 2 * np.sqrt([max(np.trace(c), 0.0) for c in trace.cov])
        ax_err.fill_between(t, 0, two_sd, color="tab:blue", alpha=0.15, label="estimate's 2σ")
        ax_err.plot(t, error, color="tab:red", lw=1.0, label="position error")
        ax_err.set_xlabel("time (s)")
        ax_err.set_ylabel("m")
        ax_err.grid(True, lw=0.3)
    axes[0][0].plot([], [], color="tab:blue", lw=0.8, label=f"2σ ellipse every {every:g} s")
    axes[0][0].legend(loc="upper left", fontsize=7)
    axes[1][0].legend(loc="upper left", fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=100)
    return out
