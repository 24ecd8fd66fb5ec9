"""A Braitenberg reader of all eight IR sensors that classifies what it sees by handle.

Written the V-REP way (the stock script, Code 4.13): deprecated object names with the
copy suffix, sim.getObjectHandle, readProximitySensor on every sensor each step. For
each detection it keeps the detected object's handle and classifies it: part of another
e-puck model (its tree), a wall, or an obstacle; and it transforms the detected point to
the world with sim.getObjectMatrix(sensor) to check it lies on the object. Prints one
JSON line.

    python braitenberg_classifier.py HOST PORT STEPS
"""

import json
import math
import sys

from coppeliasim_zmqremoteapi_client import RemoteAPIClient

client = RemoteAPIClient(sys.argv[1], int(sys.argv[2]))
sim = client.require("sim")
steps = int(sys.argv[3])

me = sim.getObjectHandle("ePuck")
left_motor = sim.getObjectHandle("ePuck_leftJoint")
right_motor = sim.getObjectHandle("ePuck_rightJoint")
sensors = [sim.getObjectHandle("ePuck_proxSensor%d" % (i + 1)) for i in range(8)]
no_detection = 0.05
max_vel = 120 * math.pi / 180
weights_left = [1, 2, -2, -1]

# every other e-puck model of the scene, and every object in its tree
others = {}
for handle in sim.getObjectsInTree(sim.handle_scene, sim.handle_all, 2):  # root objects
    is_model = (sim.getModelProperty(handle) & sim.modelproperty_not_model) == 0
    if is_model and handle != me:
        for part in sim.getObjectsInTree(handle):
            others[part] = sim.getObjectAlias(handle, 1)


def apply(matrix, point):
    return [
        sum(matrix[4 * r + c] * point[c] for c in range(3)) + matrix[4 * r + 3] for r in range(3)
    ]


seen = {}
points = []
sim.setStepping(True)
sim.startSimulation()
try:
    for _ in range(steps):
        distances = []
        for i, sensor in enumerate(sensors):
            state, distance, point, obj, normal = sim.readProximitySensor(sensor)
            if state > 0 and distance < no_detection:
                distances.append(distance)
                if obj in others:
                    kind = "robot"
                elif sim.getObjectAlias(obj).startswith("Wall"):
                    kind = "wall"
                else:
                    kind = "obstacle"
                label = others.get(obj) or sim.getObjectAlias(obj, 1)
                seen.setdefault(kind, set()).add(label)
                points.append(
                    {
                        "sensor": i + 1,
                        "object": label,
                        "kind": kind,
                        "world": apply(sim.getObjectMatrix(sensor, sim.handle_world), point),
                        "distance": distance,
                    }
                )
            else:
                distances.append(no_detection)
        vl = vr = max_vel
        for i in range(4):
            term = 1 - distances[1 + i] / no_detection
            vl += max_vel * weights_left[i] * term
            vr += max_vel * weights_left[3 - i] * term
        sim.setJointTargetVelocity(left_motor, vl)
        sim.setJointTargetVelocity(right_motor, vr)
        sim.step()
finally:
    sim.stopSimulation()

print(json.dumps({"seen": {k: sorted(v) for k, v in seen.items()}, "points": points}))
