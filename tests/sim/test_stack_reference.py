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

from puckboard.backends.embedded import open_embedded
from puckboard.behaviours import load_controller
from puckboard.control.loop import ControlLoop
from puckboard.scenario import load_scene

# (profile, controller) → (poses after 600 cycles, cycles per active layer, collisions).
# Re-recorded when the robot profiles became traceable to their sources (the physical
# e-puck's sensors at Webots' positions; V-REP's model with its cone sensors), on purpose.
REFERENCE = {
    ("epuck", "improved"): (
        [
            [0.6137803552120064, 0.08009873048189563, 1.1993682364652025],
            [-0.9039450753428439, -0.6230725998286211, -2.7673746753576838],
        ],
        {"Cruise": 751, "FrontObstacleLeftTurn": 40, "LineFollow": 324, "SideWallKeep": 85},
        [0, 0],
    ),
    ("epuck", "stock"): (
        [
            [0.5627416355749086, -1.105940365861439, -0.9582973014028782],
            [-0.6397420869724897, 0.07187566229255594, -1.875822547713756],
        ],
        {"Cruise": 761, "FrontBraitenbergAvoid": 48, "LineFollow": 368, "SideWallKeep": 23},
        [1, 1],
    ),
    ("epuck-vrep", "improved"): (
        [
            [0.6327773584698068, 0.09086845362278377, 1.9424782245019705],
            [-0.6366947992131232, 0.08049888338410693, 1.2329785566807165],
        ],
        {"Cruise": 49, "FrontObstacleLeftTurn": 39, "LineFollow": 989, "SideWallKeep": 123},
        [0, 0],
    ),
    ("epuck-vrep", "stock"): (
        [
            [-0.03960055406362359, -0.25076082704197017, 0.10433308234568674],
            [0.030757062339196464, -0.24831832543222118, -3.026110771518645],
        ],
        {"FrontBraitenbergAvoid": 1020, "LineFollow": 180},
        [1, 1],
    ),
}


@pytest.mark.parametrize(("profile", "controller"), sorted(REFERENCE))
def test_two_robot_pass_matches_the_recorded_reference(profile, controller):
    conn = open_embedded(load_scene("two-robot-pass").with_profile(profile), seed=3)
    controllers = [load_controller(controller) for _ in conn.adapters]
    loop = ControlLoop(list(zip(conn.adapters.values(), controllers)))
    layers: collections.Counter[str] = collections.Counter()
    loop.add_observer(lambda _loop: layers.update(c.active_layer for c in controllers))
    loop.run(cycles=600)
    poses, active, collisions = REFERENCE[(profile, controller)]
    expected = [value for pose in poses for value in pose]
    assert conn.world.poses.ravel().tolist() == pytest.approx(expected, abs=1e-9)
    assert dict(layers) == active
    assert conn.world.collisions.tolist() == collisions
