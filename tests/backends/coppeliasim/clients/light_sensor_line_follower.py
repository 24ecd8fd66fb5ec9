"""The stock e-puck line follower, reading the light sensor's image bytes.

Like the university's model script (the thesis's Code 2.1) it reads three values of
ePuck_lightSensor's RGB image, bytes 0, 21 and 93, and drives the stock script's line
following: a wheel slows to a quarter when its side's sensor sees the dark line.
Records the robot's path with sim.getObjectPose. Prints one JSON line.

    python light_sensor_line_follower.py HOST PORT STEPS
"""

import json
import math
import sys

from coppeliasim_zmqremoteapi_client import RemoteAPIClient

client = RemoteAPIClient(sys.argv[1], int(sys.argv[2]))
sim = client.require("sim")
steps = int(sys.argv[3])

robot = sim.getObject("/ePuck")
light = sim.getObject("/ePuck/lightSensor")
left_motor = sim.getObject("/ePuck/leftJoint")
right_motor = sim.getObject("/ePuck/rightJoint")
max_vel = 120 * math.pi / 180
resolution = sim.getVisionSensorRes(light)

path = []
dark_reads = 0
sim.setStepping(True)
sim.startSimulation()
try:
    for _ in range(steps):
        image, res = sim.getVisionSensorImg(light)
        left, centre, right = (image[k] / 255 for k in (0, 21, 93))
        vl = vr = max_vel
        if min(left, centre, right) < 0.5:
            dark_reads += 1
            vl = max_vel if left > 0.5 else 0.25 * max_vel
            vr = max_vel if right > 0.5 else 0.25 * max_vel
        sim.setJointTargetVelocity(left_motor, vl)
        sim.setJointTargetVelocity(right_motor, vr)
        sim.step()
        path.append(sim.getObjectPose(robot, sim.handle_world)[:2])
finally:
    sim.stopSimulation()

print(
    json.dumps(
        {"resolution": resolution, "bytes": len(image), "dark_reads": dark_reads, "path": path}
    )
)
