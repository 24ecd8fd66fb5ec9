"""Go home by odometry: follow the line for a while, then drive back to where you started.

The robot has no GPS. It knows where it is only by adding up its wheel rotations, which
an :class:`~puckboard.estimation.OdometrySource` does for it: a knowledge source that
reads the ``encoders`` key each control cycle and writes ``estimate/pose`` (x, y, θ
relative to the start) and ``estimate/pose_cov`` (how unsure that is) before the layers
tick. The :class:`~puckboard.behaviours.GoHome` layer reads the estimate and, after
``after`` seconds, suppresses line following and steers to the origin of that frame:
the start.

What to watch: the estimate says "home" (distance 0); the simulator's ground truth says
how far from the real start the robot actually stopped. The simulated e-puck, like the
real one, drives its wheels with stepper motors and counts the *commanded* steps, while
its body moves by what the wheels' grip on the floor allows (the scene's 3 % wheel
noise). That slip is invisible to odometry, so the robot stops centimetres away from where
it believes home is, and the estimate's σ says how far it may be. Run it with
``--no-slip`` (wheel noise 0) to see the estimate and the truth agree.

Run it: ``python examples/go_home.py [--duration 120] [--after 60] [--seed 0] [--no-slip]``
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from puckboard.behaviours import Controller, Cruise, GoHome, LineFollow
from puckboard.control.episode import Episode
from puckboard.estimation import OdometrySource


def controller(after: float) -> Controller:
    return Controller(
        [GoHome(after=after, tolerance=0.01), LineFollow(recovery=True), Cruise()],
        name="line, then home",
    )


def main(
    duration: float = 120.0, seed: int = 0, *, after: float = 60.0, slip: bool = True
) -> dict[str, Any]:
    """Follow the line for ``after`` s, go home until ``duration``; return what was measured."""
    overrides = {} if slip else {"noise.wheel_speed": 0.0}
    episode = Episode(
        "line-follow", controller=lambda: controller(after), seed=seed, overrides=overrides
    )
    robot = episode.connection.adapters[episode.world.robot_names[0]]
    start = episode.world.poses[0].copy()
    OdometrySource().attach(episode.loop)
    episode.run(duration=duration, stop_early=False)
    est = robot.ns.value("estimate/pose")
    cov = robot.ns.value("estimate/pose_cov")
    end = episode.world.poses[0]
    return {
        "estimated distance from home (m)": round(math.hypot(est.x, est.y), 4),
        "true distance from the start (m)": round(
            math.hypot(end[0] - start[0], end[1] - start[1]), 4
        ),
        "estimate's position sigma (m)": round(math.sqrt(cov[0, 0] + cov[1, 1]), 4),
    }


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=120.0)
    parser.add_argument("--after", type=float, default=60.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-slip", action="store_true", help="turn the wheel noise off")
    args = parser.parse_args()
    result = main(args.duration, args.seed, after=args.after, slip=not args.no_slip)
    for key, value in result.items():
        print(f"{key:36s} {value}")
