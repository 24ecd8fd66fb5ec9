"""The tutorial's controller, as docs/tutorial.md has a student save it (``my_controller.py``).

The benchmarks time a student's code beside the shipped controllers, and the documents
are not installed with the package, so the file the tutorial saves is kept here; a test
keeps it equal to the tutorial's block (tests/bench/test_bench_transfer.py).
"""

from __future__ import annotations

__all__ = ["FILE_NAME", "SOURCE"]

#: The name the tutorial saves it under, and its factory (``my_controller.py:my_controller``).
FILE_NAME = "my_controller.py"

#: The file's text, exactly as the tutorial's block shows it.
SOURCE = """# my_controller.py
from puckboard import Controller, Cruise, Layer, LineFollow, SideWallKeep, WheelCommand


class TurnLeftFirst(Layer):
    reads = ("proximity",)

    def __init__(self, speed=2.0):
        super().__init__()
        self.speed = speed

    def applies(self, frame):
        prox = frame.proximity
        if prox is None:
            return False
        front = [prox.diagonal_left, prox.front_left, prox.front_right, prox.diagonal_right]
        return min(front) < prox.range

    def command(self, frame):
        return WheelCommand(-self.speed / 2, self.speed)


class FindLineOnTheRight(Layer):
    reads = ("ground",)

    def __init__(self, speed=2.0, ratio=0.8):
        super().__init__()
        self.speed = speed
        self.ratio = ratio

    def applies(self, frame):
        ground = frame.ground
        return ground is not None and not ground.dark().any()

    def command(self, frame):
        return WheelCommand(self.speed, self.ratio * self.speed)


def my_controller():
    return Controller(
        [
            TurnLeftFirst(),
            LineFollow(inner_factor=0.2, recovery=True),
            SideWallKeep(("right",)),
            FindLineOnTheRight(),
            Cruise(),
        ],
        name="my controller",
        requires=("proximity",),
    )


# the name a class challenge grades (see "Hand it in" at the end)
def make_controller(**params):
    return my_controller()
"""
