"""The full stack's behaviour, pinned: speed work on the blackboard, the arbiter or the
simulator must not change a single decision.

The reference figures were recorded before the hot paths were optimised (blackboard
writes, namespace snapshots, layer ticks, trusted records) and every optimisation left
them bit-identical. A change that alters behaviour on purpose must re-record them and
say why (below, with the figures: last when the engine came to simulate each robot as
built, with the one IR conversion of the real robot). Poses are compared to 1e-9 m/rad
so that a different platform's last-bit libm differences do not fail the test; which
layer drove, and how often, is compared exactly.
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
# e-puck's sensors at Webots' positions; V-REP's model with its cone sensors), on purpose;
# and again, on purpose, when each robot came to be simulated as built: the physical
# e-puck reports calibrated IR values and the distances they convert to, as the real
# robot does (no separate distance noise any more), and V-REP's model reads its ground
# sensors as the single pixels they are (a point sample, no 2 mm footprint).
REFERENCE = {
    ("epuck", "improved"): (
        [
            [0.6241437131771279, 0.04846678152922609, 1.144344199334448],
            [-0.9300007951913265, -0.5510322899376735, -2.8425310011471416],
        ],
        {"Cruise": 761, "FrontObstacleLeftTurn": 38, "LineFollow": 331, "SideWallKeep": 70},
        [0, 0],
    ),
    ("epuck", "stock"): (
        [
            [0.7441567883261065, -0.956613822935399, -0.7392706924624171],
            [-0.6129292594798997, 0.13162235007424494, -2.113619479761619],
        ],
        {"Cruise": 688, "FrontBraitenbergAvoid": 51, "LineFollow": 422, "SideWallKeep": 39},
        [1, 1],
    ),
    ("epuck-vrep", "improved"): (
        [
            [0.6496911206852374, 0.009923132973948107, 1.5712327043951697],
            [-0.990676236539305, -0.3692212970238917, -3.0405513060551943],
        ],
        {"Cruise": 671, "FrontObstacleLeftTurn": 40, "LineFollow": 387, "SideWallKeep": 102},
        [0, 0],
    ),
    ("epuck-vrep", "stock"): (
        [
            [-0.03994629141941323, -0.249248079955816, -0.08048502286005746],
            [0.030450630475753852, -0.24858975808488523, -3.0692057525054186],
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
