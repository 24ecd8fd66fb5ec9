"""Switch backend — embedded simulator → CoppeliaSim → real robot — in one line.

The thesis's framework existed for this (its §2.1.2): a controller talks to an abstract
e-puck, so moving it from the simulator to the real robot does not change the
controller. In puckboard the backend is one argument. Everything else in this file —
the scene, the controller, the judge, the printed outcome — stays the same.

Pick one ``BACKEND`` line (the first is the default and needs nothing installed)::

    BACKEND, OPTIONS = "embedded", {}
    # CoppeliaSim (pip install 'puckboard[coppeliasim]') with the e-puck scene loaded and
    # its ZeroMQ remote API add-on running -- or a class simulation served by a lecturer
    # with `puckboard serve line-follow --host 0.0.0.0`:
    BACKEND, OPTIONS = "coppeliasim", {"host": "127.0.0.1"}
    # A real e-puck2 over Wi-Fi (selector on 15, Wi-Fi firmwares flashed); the robot is
    # not seeded, and its pose is not known, so only what it senses is reported:
    BACKEND, OPTIONS = "epuck2-wifi", {"host": "192.168.1.42"}
    # A real e-puck over Bluetooth / USB (advanced sercom, pip install 'puckboard[real]'):
    BACKEND, OPTIONS = "sercom", {"device": "/dev/rfcomm0"}

No robot at hand? ``puckboard emulate line-follow --port 10000`` runs a simulated e-puck
that speaks the real robot's Wi-Fi protocol; then use
``BACKEND, OPTIONS = "epuck2-wifi", {"host": "127.0.0.1", "port": 10000}``.

The same switch on the command line::

    puckboard run line-follow --backend embedded
    puckboard run line-follow --backend epuck2-wifi --host 192.168.1.42

What to watch: nothing in ``main`` mentions the backend except the ``backend=`` argument.
On a real robot the loop runs in real time (Ctrl-C stops the robot safely) and its
sensor values differ from the simulator's: see the FAQ's "sim vs real".

Run it: ``python examples/switch_backend.py``
"""

from __future__ import annotations

from typing import Any

from puckboard.control.episode import run_episode

BACKEND: str
OPTIONS: dict[str, Any]
BACKEND, OPTIONS = "embedded", {}  # ← the one line to change; see the docstring


def main(
    duration: float = 30.0,
    seed: int = 0,
    backend: str = BACKEND,
    options: dict[str, Any] | None = None,
) -> Any:
    """Follow the line of the ``line-follow`` scene with the improved controller."""
    return run_episode(
        "line-follow",
        controller="improved",
        seed=seed,
        duration=duration,
        backend=backend,
        stop_early=False,
        **(OPTIONS if options is None else options),
    )


if __name__ == "__main__":
    result = main()
    robot = result.robots[0]
    print(
        f"[{BACKEND}] {result.sim_time_s:.0f} s: drove {robot.distance_m:.2f} m, "
        f"on the line {100 * robot.on_line_fraction:.0f} % of the time"
    )
