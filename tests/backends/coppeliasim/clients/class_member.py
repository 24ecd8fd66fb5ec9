"""One student's client in a class that shares one simulation: the loop the docs show.

docs/coppeliasim.md ("A class of stepping clients") quotes the block between the two
marker comments verbatim (a test checks it): stepping mode before the start, a wait until
somebody starts the simulation (sim.step would return at once before that, and the loop
would run ahead of everybody), and sim.setStepping(False) when leaving, so that nobody
waits for a client that has gone. Prints one JSON line: the simulation time after the
loop.

    python class_member.py HOST PORT STEPS
"""

import json
import sys
import time

from coppeliasim_zmqremoteapi_client import RemoteAPIClient

client = RemoteAPIClient(sys.argv[1], int(sys.argv[2]))
sim = client.require("sim")
steps = int(sys.argv[3])

# -- the class loop --
sim.setStepping(True)  # from now on the simulation waits for this client's sim.step
while sim.getSimulationState() == sim.simulation_stopped:
    time.sleep(0.1)  # until the lecturer (or a classmate) starts the simulation
try:
    for _ in range(steps):
        # read the sensors, set the wheels ...
        sim.step()
finally:
    sim.setStepping(False)  # leaving: nobody waits for this client any more
# -- end of the class loop --

print(json.dumps({"time": sim.getSimulationTime()}))
