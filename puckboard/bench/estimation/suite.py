"""The ``estimation`` suite: the cases, seeds and noise levels, and the summary over them.

Which runs make up the suite, and what it reports: the per-run figures of every trial,
their median and worst over seeds and robots, the IR filter's noise reduction and the
filters' costs (see the package docstring for what is compared and why).
"""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .costs import measure_costs
from .plot import plot_traces
from .proximity import measure_proximity
from .trial import VARIANTS, four_digits, run_case

__all__ = ["CASES", "SEEDS", "run_suite", "summarise"]

SEEDS: tuple[int, ...] = (1, 2, 3)
WHEEL_NOISE: tuple[float, ...] = (0.0, 0.03)  # 0.03: the shipped scenes' setting
LAPS = 3.0
#: (scene, laps or None for the whole scene, controller or None for the scene's).
#: The stock controller makes the two robots collide: the case odometry cannot see.
CASES: tuple[tuple[str, float | None, str | None], ...] = (
    ("two-robot-pass", None, None),
    ("two-robot-pass", None, "stock"),
    ("line-follow", LAPS, None),
)
LINE_FOLLOW_CASES = tuple(case for case in CASES if case[0] == "line-follow")


def run_suite(
    steps: int | None = None,
    seeds: Sequence[int] = SEEDS,
    *,
    gyro_noise: float = 0.0,
    gyro_bias: float = 0.0,
    settle: float = 0.0,
    cases: str | Sequence[tuple[str, float | None, str | None]] = CASES,
    plot: Path | None = None,
    plot_contact: Path | None = None,
) -> dict[str, Any]:
    """The ``estimation`` benchmark suite (see the package docstring).

    ``steps`` caps each run's control cycles (a quick smoke run); ``None`` runs the two-robot
    pass to its verdict and line-follow for three laps. ``gyro_noise``, ``gyro_bias``: the
    simulated gyro's σ and offset (rad/s); ``settle`` (s) of standing still first (see
    :func:`~.trial.run_case`). ``cases``: which of :data:`CASES` to run, or ``"all"`` /
    ``"line-follow"`` (its three laps only: a quicker comparison of the estimates).
    ``plot`` draws line-follow (first seed) against the truth there; ``plot_contact`` draws
    the stock two-robot pass (a collision, last seed).
    """
    for name, value, low, high in (
        ("gyro_noise", gyro_noise, 0.0, 1.0),
        ("gyro_bias", gyro_bias, -1.0, 1.0),
        ("settle", settle, 0.0, 60.0),
    ):
        if not low <= value <= high:
            raise ValueError(f"{name} must lie in [{low}, {high}], got {value}")
    if isinstance(cases, str):
        named = {"all": CASES, "line-follow": LINE_FOLLOW_CASES}
        if cases not in named:
            raise ValueError(f"cases must be one of {sorted(named)}, got {cases!r}")
        cases = named[cases]
    runs = []
    for scene_name, laps, controller in cases:
        for noise in WHEEL_NOISE:
            for seed in seeds:
                info, _ = run_case(
                    scene_name,
                    noise,
                    seed,
                    steps=steps,
                    laps=laps,
                    controller=controller,
                    gyro_noise=gyro_noise,
                    gyro_bias=gyro_bias,
                    settle=settle,
                )
                runs.append(info)
    return {
        "seeds": list(seeds),
        "wheel_noise": list(WHEEL_NOISE),
        "gyro_noise": gyro_noise,
        "gyro_bias": gyro_bias,
        "settle_s": settle,
        "variants": list(VARIANTS),
        "summary": summarise(runs),
        "proximity": measure_proximity(),
        "costs": measure_costs(),
        "runs": runs,
        "plots": _draw_plots(seeds, steps, plot, plot_contact),
    }


def _draw_plots(
    seeds: Sequence[int], steps: int | None, plot: Path | None, plot_contact: Path | None
) -> list[str]:
    written = []
    if plot is not None:
        _, traces = run_case("line-follow", 0.03, seeds[0], steps=steps, laps=LAPS)
        keep = [t for t in traces if t.variant in VARIANTS]
        title = f"line-follow, 3 laps, wheel noise 3 %, seed {seeds[0]}"
        written.append(str(plot_traces(keep, plot, title=title)))
    if plot_contact is not None:
        seed = seeds[-1]
        _, traces = run_case("two-robot-pass", 0.03, seed, steps=steps, controller="stock")
        written.append(
            str(
                plot_traces(
                    [t for t in traces if t.variant == "encoders"],
                    plot_contact,
                    every=20.0,
                    title=(
                        f"two-robot pass, stock controllers (they collide), wheel noise 3 %, "
                        f"seed {seed}"
                    ),
                )
            )
        )
    return written


def summarise(runs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Median (and max) over seeds and robots, per scene × wheel noise × variant."""
    groups: dict[tuple[str, float, str], list[dict[str, float]]] = {}
    for run in runs:
        for robot in run["robots"]:
            for variant in VARIANTS:
                groups.setdefault((run["scene"], run["wheel_noise"], variant), []).append(
                    robot[variant]
                )
    rows = []
    for (scene, noise, variant), ms in groups.items():
        row: dict[str, Any] = {
            "scene": scene,
            "wheel_noise": noise,
            "variant": variant,
            "n": len(ms),
        }
        for key in (
            "final_position_error_m",
            "final_heading_error_deg",
            "max_position_error_m",
            "distance_m",
            "inside_95_fraction",
        ):
            values = [m[key] for m in ms]
            row[key] = four_digits(statistics.median(values))
            if key == "inside_95_fraction":
                row[key + "_min"] = four_digits(min(values))
            else:
                row[key + "_max"] = four_digits(max(values))
        rows.append(row)
    return rows
