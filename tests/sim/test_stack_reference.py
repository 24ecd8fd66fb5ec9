"""The full stack's behaviour, pinned: speed work on the blackboard, the arbiter or the
simulator must not change a single decision.

The reference figures were recorded before the hot paths were optimised (blackboard
writes, namespace snapshots, layer ticks, trusted records) and every optimisation left
them bit-identical. A change that alters behaviour on purpose must re-record them and
say why. Poses are compared to 1e-9 m/rad so that a different platform's last-bit libm
differences do not fail the test; which layer drove, and how often, is compared exactly.
"""

from __future__ import annotations

import collections

import pytest

from puckboard.adapters.embedded import open_embedded
from puckboard.behaviours import load_controller
from puckboard.control.loop import ControlLoop

REFERENCE = {
    "improved": (
        [
            [0.6404983084191903, 0.06655247245960975, 1.8516874595178296],
            [-0.6411372307598783, 0.06406507120697529, 1.31256605636199],
        ],
        {"Cruise": 130, "FrontObstacleLeftTurn": 38, "LineFollow": 920, "SideWallKeep": 112},
        [0, 0],
    ),
    "stock": (
        [
            [0.5149789856868189, -1.1507692272897287, -1.0196036429690392],
            [-0.6395746406923817, 0.07245030589699915, -1.854062863767645],
        ],
        {"Cruise": 767, "FrontBraitenbergAvoid": 40, "LineFollow": 378, "SideWallKeep": 15},
        [1, 1],
    ),
}


@pytest.mark.parametrize("controller", sorted(REFERENCE))
def test_two_robot_pass_matches_the_recorded_reference(controller):
    conn = open_embedded("two-robot-pass", seed=3)
    controllers = [load_controller(controller) for _ in conn.adapters]
    loop = ControlLoop(list(zip(conn.adapters.values(), controllers)))
    layers: collections.Counter[str] = collections.Counter()
    loop.add_observer(lambda _loop: layers.update(c.active_layer for c in controllers))
    loop.run(cycles=600)
    poses, active, collisions = REFERENCE[controller]
    expected = [value for pose in poses for value in pose]
    assert conn.world.poses.ravel().tolist() == pytest.approx(expected, abs=1e-9)
    assert dict(layers) == active
    assert conn.world.collisions.tolist() == collisions
