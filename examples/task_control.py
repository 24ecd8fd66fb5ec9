"""Task control architecture: a tree of tasks, each started by its parent, in order.

In the task control architecture (thesis §2.1.1, Figures 2.2–2.3) a mission is a *task
tree*: a parent task starts its child tasks, and temporal constraints say which runs
after which. Behaviour trees are the modern form of task trees, and each of puckboard's
layers runs in its controller's tree as a py_trees behaviour (``as_behaviour(layer)``
hands it to a py_trees composite of your own), so a task tree is built from the same
parts:

* a ``Sequence`` (with memory) runs its children one after another: the next task starts
  when the previous one *succeeds*;
* a ``Selector`` picks the first child that applies: inside a task, the usual layers
  (follow the line, else cruise) do the driving;
* ``Task`` (defined below) is a decorator that runs its child until a goal measured on
  the wheel encoders is reached, then succeeds.

The mission, on the ``line-follow`` scene::

    mission (Sequence)
    ├── follow the line for 1 m   (Task → Selector: LineFollow, Cruise)
    ├── turn around               (Task → Spin)
    ├── follow the line for 0.5 m (Task → Selector: LineFollow, Cruise)
    └── Stop                      (holds the wheels at zero: mission complete)

What to watch:

* the printed tree after the run: ``[o]`` marks tasks that succeeded, ``[*]`` the one
  running now (``Stop``), ``[-]`` ones not ticked in the last tick;
* the tasks finish in order, each at the time printed; after the last one the robot
  stands still (a plain Selector would have restarted the mission from the top).

Run it: ``python examples/task_control.py``
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import py_trees
from py_trees.common import Status

from puckboard.behaviours import (
    Controller,
    Cruise,
    Frame,
    Layer,
    LineFollow,
    TickContext,
    as_behaviour,
)
from puckboard.control.episode import Episode
from puckboard.profile import EPUCK2
from puckboard.records import WheelCommand, WheelEncoders

R, AXLE = EPUCK2.wheel_radius, EPUCK2.axle_length


def distance_driven(start: WheelEncoders, now: WheelEncoders) -> float:
    """Metres driven by the robot's centre since ``start`` (odometry)."""
    return R * ((now.left - start.left) + (now.right - start.right)) / 2.0


def angle_turned(start: WheelEncoders, now: WheelEncoders) -> float:
    """Radians turned (counter-clockwise positive) since ``start`` (odometry)."""
    return R * ((now.right - start.right) - (now.left - start.left)) / AXLE


class Task(py_trees.decorators.Decorator):
    """Run ``child`` until ``progress(start, now) >= goal``; then SUCCESS.

    ``progress`` measures on the wheel encoders since the task started. ``finished_at``
    is the simulation time the goal was reached (``None`` until then).
    """

    reads = ("encoders",)

    def __init__(
        self,
        name: str,
        child: py_trees.behaviour.Behaviour,
        progress: Callable[[WheelEncoders, WheelEncoders], float],
        goal: float,
    ) -> None:
        super().__init__(name=name, child=child)
        self.progress = progress
        self.goal = goal
        self.finished_at: float | None = None
        self._start: WheelEncoders | None = None

    def setup(self, **kwargs: Any) -> None:
        self.context: TickContext | None = kwargs.get("context")  # holds the tick's Frame

    def initialise(self) -> None:
        self._start = None  # measure from the first tick of this task

    def update(self) -> Status:
        assert self.context is not None and self.context.frame is not None, (
            "a Task runs inside a Controller"
        )
        frame: Frame = self.context.frame
        encoders = frame.value("encoders")
        if encoders is None:
            return Status.RUNNING
        if self._start is None:
            self._start = encoders
        if self.progress(self._start, encoders) >= self.goal:
            self.finished_at = frame.time
            return Status.SUCCESS
        return self.decorated.status


class Spin(Layer):
    """Turn on the spot, counter-clockwise."""

    def __init__(self, speed: float = 2.0) -> None:
        super().__init__()
        self.speed = speed

    def command(self, frame: Frame) -> WheelCommand:
        return WheelCommand(-self.speed, self.speed)


class Stop(Layer):
    """Hold the wheels at zero: the mission is complete."""

    def command(self, frame: Frame) -> WheelCommand:
        return WheelCommand.stop()


def follow_line(metres: float) -> Task:
    """A task: follow the line (else cruise) until ``metres`` have been driven.

    Its layers carry the distance in their names, so ``command/layer`` (and the drawn
    tree) tell the two line-following tasks apart.
    """
    drive = py_trees.composites.Selector(
        f"line or cruise ({metres:g} m)",
        memory=False,
        children=[
            as_behaviour(LineFollow(recovery=True, name=f"LineFollow ({metres:g} m)")),
            as_behaviour(Cruise(name=f"Cruise ({metres:g} m)")),
        ],
    )
    return Task(f"follow the line for {metres:g} m", drive, distance_driven, metres)


def mission() -> Controller:
    tasks = py_trees.composites.Sequence(
        "mission",
        memory=True,
        children=[
            follow_line(1.0),
            Task("turn around", as_behaviour(Spin()), angle_turned, 3.1),
            follow_line(0.5),
            as_behaviour(Stop()),
        ],
    )
    return Controller([tasks], name="task-control")


def main(duration: float = 60.0, seed: int = 0) -> dict[str, Any]:
    """Run the mission; return when each task finished and who drove at the end."""
    episode = Episode("line-follow", controller=mission, seed=seed)
    episode.run(duration, stop_early=False)  # the line-following judge would stop a U-turn
    controller = episode.controllers["epuck"]
    finished = {
        node.name: node.finished_at for node in controller.root.iterate() if isinstance(node, Task)
    }
    print(controller.ascii_tree())
    return {
        "finished": finished,
        "final_layer": controller.active_layer,
        "distance_m": episode.judge.metrics()[0].distance_m,
    }


if __name__ == "__main__":
    out = main()
    for task, when in out["finished"].items():
        print(f"{task:28s} {'not finished' if when is None else f'done at {when:5.1f} s'}")
    print(f"in control at the end: {out['final_layer']}")
