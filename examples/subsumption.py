"""Subsumption architecture: layers of whole behaviours, arbitrated by priority.

In Brooks' subsumption architecture (thesis §2.1.1, Figure 2.4) every level is a complete
behaviour with an activation condition; when a higher level's condition holds, its action
*suppresses* everything below it. puckboard's :class:`~puckboard.behaviours.Controller`
is that arbiter: a py_trees Selector without memory that, every tick, gives the wheels to
the first layer (highest priority first) that applies.

The controller here is the thesis's improved controller with one change: the avoidance
layer is wrapped in :class:`~puckboard.behaviours.HoldFor`, a suppressor with a timer,
so once it has taken over it keeps the wheels for ``HOLD`` seconds after the obstacle
leaves the front sensors::

    1. HoldFor(FrontObstacleLeftTurn, 0.3 s)   something in front → turn left
    2. LineFollow                              a ground sensor sees the line
    3. SideWallKeep (right)                    obstacle on the right → hug it
    4. Cruise                                  always

Two robots run it in the ``two-robot-pass`` scene. After every cycle the example notes,
for each robot, whether an obstacle was within range of a front sensor and which layer
had the wheels (the ``command/layer`` blackboard key).

What to watch:

* ``avoid_when_close``: whenever something was in front, the avoidance layer was in
  control — it suppresses line following even while the line is right under the robot;
* ``held_after``: cycles in which nothing was in front any more but the avoidance layer
  still drove — that is HoldFor's timer at work;
* the layer time shares, and the outcome: holding the left turn has a price. Each held
  turn takes the robot further from the line, and with ``HOLD = 0.3`` the pass fails
  (``turned_back``, seed 0) where the unheld improved controller passes. Set ``HOLD = 0``
  and compare: a timer is a tool for manoeuvres that must finish, not a free extra.

Run it: ``python examples/subsumption.py``
"""

from __future__ import annotations

from collections import Counter
from typing import Any

from puckboard.behaviours import (
    Controller,
    Cruise,
    FrontObstacleLeftTurn,
    HoldFor,
    LineFollow,
    SideWallKeep,
)
from puckboard.behaviours.obstacle import obstacle_in_front
from puckboard.control.episode import Episode

HOLD = 0.3  # s of suppression after the obstacle has left the front sensors
AVOID = "FrontObstacleLeftTurn"


def held_left_turn() -> Controller:
    return Controller(
        [
            HoldFor(FrontObstacleLeftTurn(), HOLD),
            LineFollow(inner_factor=0.20, recovery=True),
            SideWallKeep(("right",)),
            Cruise(),
        ],
        name="held-left-turn",
        requires=("proximity",),
    )


def main(duration: float = 120.0, seed: int = 0) -> dict[str, Any]:
    """Run the two-robot pass; return arbitration counts and the episode's result."""
    episode = Episode("two-robot-pass", controller=held_left_turn, seed=seed)
    counts: Counter[str] = Counter()
    share: Counter[str] = Counter()

    def watch(ep: Episode) -> None:
        for name in ep.controllers:
            ns = ep.blackboard.namespace(name)
            prox = ns.get("proximity").value
            layer = ns.get("command/layer").value
            share[layer] += 1
            if obstacle_in_front(prox):
                counts["close"] += 1
                counts["avoid_when_close"] += layer == AVOID
            elif layer == AVOID:
                counts["held_after"] += 1

    episode.add_observer(watch)
    result = episode.run(duration)
    total = sum(share.values())
    return {
        "close": counts["close"],
        "avoid_when_close": counts["avoid_when_close"],
        "held_after": counts["held_after"],
        "layer_share": {k: v / total for k, v in share.most_common()},
        "result": result,
    }


if __name__ == "__main__":
    out = main()
    print(
        f"something in front in {out['close']} robot-cycles; the avoidance layer drove in "
        f"{out['avoid_when_close']} of them and held on for {out['held_after']} more"
    )
    for layer, fraction in out["layer_share"].items():
        print(f"  {layer:24s} {100 * fraction:5.1f} % of the time")
    result = out["result"]
    print(f"two-robot pass: {'passed' if result.success else f'failed ({result.failure})'}")
