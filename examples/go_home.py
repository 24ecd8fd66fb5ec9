"""Go home by odometry: follow the line for a while, then drive back to where you started.

The robot has no GPS. It knows where it is only by adding up its wheel rotations, which
an :class:`~puckboard.estimation.OdometrySource` does for it: a knowledge source that
reads the ``encoders`` key each control cycle and writes ``estimate/pose`` (x, y, θ
relative to the start) and ``estimate/pose_cov`` (how unsure that is) before the layers
tick. The :class:`~puckboard.behaviours.GoHome` layer reads the estimate and, after
``after`` seconds, suppresses line following and steers to the origin of that frame:
the start.

What to watch: the estimate says "home" (distance 0); the simulator's ground truth says
how far from the real start the robot actually stopped. On the embedded simulator the
encoders see every wheel rotation and the body follows the wheels, so the two agree to
well under a centimetre unless the robot touched something. Then run it with
``--step-counter`` to see what a real e-puck does: its step counters count the
*commanded* steps, and the wheels' 3 % speed noise becomes drift, so the robot stops
centimetres away from where it believes home is -- and the estimate's σ says so.
(``CommandedSteps`` below is a second knowledge source, ten lines, that plays the step
counter; the odometry source is simply pointed at its key.)

Run it: ``python examples/go_home.py [--duration 120] [--after 60] [--seed 0] [--step-counter]``
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from puckboard.behaviours import Controller, Cruise, GoHome, LineFollow
from puckboard.blackboard import Snapshot
from puckboard.episode import Episode
from puckboard.estimation import OdometrySource
from puckboard.knowledge import KnowledgeSource
from puckboard.records import WheelEncoders


class CommandedSteps(KnowledgeSource):
    """What a real e-puck's step counters report: the commanded wheel speeds, integrated.

    It writes ``steps/encoders``; an :class:`OdometrySource` with
    ``encoders_key="steps/encoders"`` then estimates from those instead of the encoders.
    """

    reads = ("command/wheels",)
    writes = ("steps/encoders",)

    def __init__(self, dt: float, limit: float, **kwargs: Any) -> None:
        self.dt, self.limit = dt, limit
        self.left = self.right = 0.0
        super().__init__(**kwargs)

    def compute(self, inputs: Snapshot) -> dict[str, WheelEncoders]:
        cmd = inputs.value("command/wheels")
        self.left += max(-self.limit, min(self.limit, cmd.left)) * self.dt
        self.right += max(-self.limit, min(self.limit, cmd.right)) * self.dt
        return {"steps/encoders": WheelEncoders(self.left, self.right)}


def controller(after: float) -> Controller:
    return Controller(
        [GoHome(after=after, tolerance=0.01), LineFollow(recovery=True), Cruise()],
        name="line, then home",
    )


def main(
    duration: float = 120.0, seed: int = 0, *, after: float = 60.0, step_counter: bool = False
) -> dict[str, Any]:
    """Follow the line for ``after`` s, go home until ``duration``; return what was measured."""
    episode = Episode("line-follow", controller=lambda: controller(after), seed=seed)
    robot = episode.connection.adapters[episode.world.robot_names[0]]
    start = episode.world.poses[0].copy()
    if step_counter:
        CommandedSteps(episode.loop.period, robot.profile.max_wheel_speed).attach(episode.loop)
        OdometrySource(encoders_key="steps/encoders").attach(episode.loop)
    else:
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
    parser.add_argument("--step-counter", action="store_true", help="estimate as a real e-puck")
    args = parser.parse_args()
    result = main(args.duration, args.seed, after=args.after, step_counter=args.step_counter)
    for key, value in result.items():
        print(f"{key:36s} {value}")
