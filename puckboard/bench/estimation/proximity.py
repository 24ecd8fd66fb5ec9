"""The IR filter on the simulator's sensor model: raw against filtered front distances.

The :class:`~puckboard.estimation.ProximityFilter` is justified by how much noise it
removes and how little bias it adds; measured on a robot standing still in front of a
wall, against a noise-free world at the same pose, so the truth is exact.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ...estimation.proximity import ProximityFilter
from .trial import four_digits

__all__ = ["measure_proximity"]


def measure_proximity(
    gaps: Sequence[float] = (0.01, 0.02, 0.03, 0.04),
    *,
    noise: float = 0.05,
    seed: int = 1,
    steps: int = 400,
) -> list[dict[str, float]]:
    """A robot standing still in front of a wall: raw against filtered front IR distances.

    For each ``gap`` (m, from the front of the body to the wall) one noise-free world gives
    the true distance of the two front sensors and one world with relative IR noise
    ``noise`` gives ``steps`` noisy readings. Reported: σ and bias (m) of the raw and the
    filtered readings (after a 20-step warm-up), and the variance ratio.
    """
    from ...scenario.scene import Arena, Noise, RobotSpec, Scene
    from ...sim.world import World

    rows = []
    for gap in gaps:
        robot = RobotSpec("still", 0.5 - 0.037 - gap, 0.0, 0.0)
        arena = Arena(-0.5, -0.4, 0.5, 0.4)

        def world(sigma: float, robot: RobotSpec = robot, arena: Arena = arena) -> Any:
            scene = Scene("wall", robots=(robot,), arena=arena, noise=Noise(proximity=sigma))
            return World(scene, seed=seed)

        truth = world(0.0).prox_distance[0, [0, 7]].copy()
        noisy = world(noise)
        flt = ProximityFilter()
        raw, filtered = [], []
        for _ in range(steps):
            noisy.step()
            z = noisy.prox_distance[0]
            out = flt.update(z, noisy.dt)
            raw.append(z[[0, 7]])
            filtered.append(out[[0, 7]])
        raw_err = np.array(raw[20:]) - truth
        out_err = np.array(filtered[20:]) - truth
        rows.append(
            {
                "gap_m": gap,
                "true_distance_m": four_digits(float(truth.mean())),
                "raw_sd_m": four_digits(float(raw_err.std(axis=0).mean())),
                "filtered_sd_m": four_digits(float(out_err.std(axis=0).mean())),
                "raw_bias_m": four_digits(float(raw_err.mean())),
                "filtered_bias_m": four_digits(float(out_err.mean())),
                "variance_ratio": four_digits(
                    float(raw_err.var(axis=0).mean() / max(out_err.var(axis=0).mean(), 1e-30))
                ),
            }
        )
    return rows
