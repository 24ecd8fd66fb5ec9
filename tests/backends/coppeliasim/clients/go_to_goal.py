"""Go to a goal dummy: a client written the way CoppeliaSim's own examples are.

It finds the robot and a dummy named Goal by alias path, reads the robot's pose with
sim.getObjectPosition / sim.getObjectOrientation, computes the goal in the robot's frame
with sim.getObjectPosition(goal, robot), and steers with a proportional law on the two
wheel joints. Stepping mode, stops the simulation at the end. Prints one JSON line.

    python go_to_goal.py HOST PORT
"""

import json
import math
import sys

from coppeliasim_zmqremoteapi_client import RemoteAPIClient

client = RemoteAPIClient(sys.argv[1], int(sys.argv[2]))
sim = client.require("sim")

robot = sim.getObject("/ePuck")
goal = sim.getObject("/Goal")
left_motor = sim.getObject("/ePuck/leftJoint")
right_motor = sim.getObject("/ePuck/rightJoint")

sim.setStepping(True)
sim.startSimulation()
reached = False
steps = 0
try:
    while steps < 1200:
        gx, gy, _ = sim.getObjectPosition(goal, robot)  # the goal seen from the robot
        distance = math.hypot(gx, gy)
        if distance < 0.02:
            reached = True
            break
        bearing = math.atan2(gy, gx)
        forward = min(0.05, 0.5 * distance) * max(0.0, math.cos(bearing))
        turn = 2.0 * bearing
        half_axle, wheel = 0.027, 0.02118
        sim.setJointTargetVelocity(left_motor, (forward - turn * half_axle) / wheel)
        sim.setJointTargetVelocity(right_motor, (forward + turn * half_axle) / wheel)
        sim.step()
        steps += 1
    x, y, _ = sim.getObjectPosition(robot, sim.handle_world)
    heading = sim.getObjectOrientation(robot, sim.handle_world)[2]
    goal_xyz = sim.getObjectPosition(goal, sim.handle_world)
finally:
    sim.setJointTargetVelocity(left_motor, 0)
    sim.setJointTargetVelocity(right_motor, 0)
    sim.stopSimulation()

print(json.dumps({"reached": reached, "steps": steps, "robot": [x, y, heading], "goal": goal_xyz}))
