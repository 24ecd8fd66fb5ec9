"""List the scene tree the way a CoppeliaSim user explores a model.

Walks sim.getObjectsInTree from the scene root and from the first e-puck, printing each
object's alias path, deprecated name, type and parent, and checks parent/child links with
sim.getObjectParent / sim.getObjectChild. Prints one JSON line.

    python tree_walk.py HOST PORT
"""

import json
import sys

from coppeliasim_zmqremoteapi_client import RemoteAPIClient

client = RemoteAPIClient(sys.argv[1], int(sys.argv[2]))
sim = client.require("sim")

type_names = {
    getattr(sim, name): name.removeprefix("object_").removesuffix("_type")
    for name in (
        "object_shape_type",
        "object_joint_type",
        "object_dummy_type",
        "object_proximitysensor_type",
        "object_visionsensor_type",
        "object_light_type",
    )
}


def describe(handle):
    parent = sim.getObjectParent(handle)
    children = []
    index = 0
    while True:
        child = sim.getObjectChild(handle, index)
        if child == -1:
            break
        children.append(sim.getObjectAlias(child))
        index += 1
    return {
        "path": sim.getObjectAlias(handle, 2),
        "name": sim.getObjectName(handle),
        "type": type_names.get(sim.getObjectType(handle), "other"),
        "parent": sim.getObjectAlias(parent) if parent != -1 else None,
        "children": children,
    }


scene = [describe(h) for h in sim.getObjectsInTree(sim.handle_scene)]
model = [describe(h) for h in sim.getObjectsInTree(sim.getObject("/ePuck"))]
print(json.dumps({"scene": scene, "model": model}))
