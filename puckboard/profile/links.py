"""The timing of the links a controller drives an e-puck over, each range with its sources.

A controller on a host PC ticks once per control *period* and acts with some *latency*:
the sensing it sees is already old, and its command takes a while to reach the wheels.
In the thesis's V-REP loop both are fixed by the simulator (one tick per 50 ms step, no
delay); on a real link they are the link's. The simulator takes both as
``control.period`` and ``control.latency`` (:class:`~puckboard.scenario.scene.Control`).

Each :class:`LinkTiming` gives a (low, high) range in seconds for both, with the sources
that bound it; where no source gives a number the range is marked ``assumed``, as the
profiles' ``ir_gain`` is. The latency is one number, the sum of the sensing's age and
the command's way to the wheels: the host shares no clock with the robot, so only the
whole round trip can be timed, and that is all the sources report.
:func:`draw_timing` draws one (period, latency) from a link (a simulation rounds it to
its whole steps); ``puckboard calibrate link`` measures your own robot's (:mod:`.link_measure`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ProfileError

__all__ = ["LINKS", "LONGEST_LINK_S", "LinkTiming", "draw_timing", "get_link", "link_names"]

#: Bits a serial line sends per byte: start bit, 8 data bits, stop bit (8N1).
_BITS_PER_BYTE = 10
#: The e-puck1's Bluetooth module talks to the robot at 115,200 baud (GCtronic).
_EPUCK1_BAUD = 115_200
#: One sercom cycle of the e-puck1 as the sercom adapter runs it: speeds, proximity,
#: ground, steps, accelerometer, ambient in one write (1 + 4 + 5 + 1 = 11 bytes) and
#: one reply (16 + 6 + 4 + 6 + 16 = 48 bytes); puckboard.backends.epuck.sercom_link.
_EPUCK1_CYCLE_BYTES = 11 + 48
#: One e-puck2 cycle: [-0x09][19-byte actuators][-0x08][0] out, 103 bytes back
#: (GCtronic's e-puck2 driver: OUTPUT_BUFF_SIZE 22, INPUT_BUFF_SIZE 103).
_EPUCK2_CYCLE_BYTES = 22 + 103


def _serial_seconds(n_bytes: int, baud: int = _EPUCK1_BAUD) -> float:
    """The time ``n_bytes`` take on a serial line at ``baud`` (8N1): a lower bound."""
    return n_bytes * _BITS_PER_BYTE / baud


#: The longest control period or latency (s) a link may have: a loop slower than a second
#: drives no e-puck anywhere sensible, so a bigger number is a unit mistake (ms for s).
#: A profile's ``[link]`` and the run's ``control.*`` settings are bounded by it.
LONGEST_LINK_S = 1.0


@dataclass(frozen=True)
class LinkTiming:
    """One link's control timing: ranges (low, high) in seconds, and their sources.

    ``period``: how often a host-side loop over this link ticks and commands; ``latency``:
    from the sensing a tick sees to the wheels turning on its command. ``sources`` says
    what bounds each end; ``assumed`` is true when some end has no source of its own.
    """

    name: str
    description: str
    period: tuple[float, float]
    latency: tuple[float, float]
    sources: tuple[str, ...]
    assumed: bool

    def __post_init__(self) -> None:
        for what, (low, high) in (("period", self.period), ("latency", self.latency)):
            if not (math.isfinite(low) and math.isfinite(high) and 0 <= low <= high):
                raise ValueError(f"link {self.name!r}: {what} must be 0 <= low <= high seconds")
        if self.period[0] <= 0:
            raise ValueError(f"link {self.name!r}: a period must be positive seconds")


_E1_LOW = _serial_seconds(_EPUCK1_CYCLE_BYTES)  # 5.1 ms
_E2_LOW = _serial_seconds(_EPUCK2_CYCLE_BYTES)  # 10.9 ms at the same rate

LINKS: dict[str, LinkTiming] = {
    link.name: link
    for link in (
        LinkTiming(
            name="coppeliasim-sync",
            description="the thesis's loop: V-REP/CoppeliaSim stepped synchronously, one "
            "tick per 50 ms simulation step; the simulator waits for the client, so no "
            "simulated time passes between sensing and command",
            period=(0.05, 0.05),
            latency=(0.0, 0.0),
            sources=(
                "thesis §2.3.2 and §2.4.3, Figure 2.13: in synchronous mode the simulation "
                "advances one step per trigger and waits for the client's calls",
                "V-REP/CoppeliaSim's default simulation step: 50 ms (e-Yantra MOOC "
                "transcript; the shipped scenes' dt)",
            ),
            assumed=False,
        ),
        LinkTiming(
            name="coppeliasim-realtime",
            description="the thesis's measured loop: V-REP in real-time mode, the "
            "framework's blocking remote API calls (sensors streamed as one string "
            "signal, the motor speeds set by a script call)",
            period=(0.068, 0.206),
            latency=(0.0, 0.07),
            sources=(
                "period: thesis §5.1.5, average loop time 67.96 ms with all sensors in one "
                "call (test 02) up to 205.86 ms addressing two sensors one by one (test 03)",
                "latency high: thesis §5.1.5, a blocking call returns once the simulator "
                "has served it, 67.77-70.12 ms on average (tests 01-03), so a command "
                "acts within about one such call; low: a call served at once",
            ),
            assumed=False,
        ),
        LinkTiming(
            name="epuck2-wifi",
            description="e-puck2 over Wi-Fi (selector 15, TCP port 1000): one 21-byte "
            "command, one 104-byte sensor packet per tick, no image",
            period=(0.05, 0.1),
            latency=(0.005, 0.04),
            sources=(
                "latency low: the firmware samples the proximity sensors at 100 Hz "
                "(e-puck2_main-processor src/sensors/proximity.c), so a reading is up to "
                "10 ms old, 5 ms on average",
                "latency high: UNIFR_API_EPUCK benchmark examples_benchmark/1_go_on_benchmark/"
                "data/results_go_on_wifi_no_image.json, 620 ticks: the wait for the "
                "reply's header and body, 95th percentile 37 ms (90th 29 ms, median 1.2 ms: "
                "the script logged between ticks, so most replies had already arrived)",
                "period low: 50 ms, the first whole simulation step above that 95th "
                "percentile (and the real-robot loop's default period)",
                "period high: 100 ms assumed, a loop that also waits for the rare slow reply "
                "(the same data: 1.95 s at worst); with the image stream on, an image took "
                "median 133 ms (results_go_on_wifi_with_image.json)",
            ),
            assumed=True,
        ),
        LinkTiming(
            name="bluetooth-sercom",
            description="advanced sercom (binary) over Bluetooth RFCOMM: the e-puck1, or "
            "the e-puck2 with selector 3; one write and one reply per tick",
            period=(0.05, 0.1),
            latency=(round(_E1_LOW, 4), 0.065),
            sources=(
                f"latency low: the e-puck1's Bluetooth serial line runs at 115,200 baud; its "
                f"cycle of {_EPUCK1_CYCLE_BYTES} bytes (8N1) takes {_E1_LOW * 1e3:.1f} ms at "
                f"least (GCtronic wiki, Advanced sercom protocol; the e-puck2's "
                f"{_EPUCK2_CYCLE_BYTES}-byte cycle would take {_E2_LOW * 1e3:.1f} ms at that rate)",
                "latency high: assumed; no published e-puck Bluetooth round trip was found. "
                "A comparable small robot takes 60-64 ms per command over Bluetooth (mBot, "
                "Makeblock forum), the bound used here",
                "period: assumed 50-100 ms, a loop at least one round trip long",
            ),
            assumed=True,
        ),
        LinkTiming(
            name="usb-sercom",
            description="advanced sercom (binary) over the e-puck2's USB virtual serial "
            "port (selector 8): the same cycle as Bluetooth, on a cable",
            period=(0.01, 0.05),
            latency=(0.002, 0.01),
            sources=(
                "latency low: a full-speed USB bulk transfer is scheduled in 1 ms frames "
                "(USB 2.0 specification), so a request and its reply take 2 ms at least",
                "latency high: assumed 10 ms, one proximity sample period at the firmware's "
                "100 Hz (src/sensors/proximity.c) plus transfer",
                "period low: 10 ms, the proximity sample period: a faster loop reads the "
                "same values again; period high: assumed 50 ms",
            ),
            assumed=True,
        ),
        LinkTiming(
            name="argos-epuck",
            description="the e-puck in ARGoS as IRIDIA's AutoMoDe experiments run it: "
            "control at 10 ticks per second, simulated synchronously",
            period=(0.1, 0.1),
            latency=(0.0, 0.0),
            sources=(
                "demiurge-project AutoMoDe experiment files (aggregation_original.argos): "
                "ticks_per_second 10",
                "ARGoS senses, runs the controllers, then steps the physics with their "
                "commands: no delay beyond the tick itself",
            ),
            assumed=False,
        ),
    )
}


def link_names() -> list[str]:
    return list(LINKS)


def get_link(name: str) -> LinkTiming:
    """The link called ``name``; a one-line error naming the known links otherwise."""
    try:
        return LINKS[name]
    except KeyError:
        raise ProfileError(
            f"unknown link {name!r}; links: {', '.join(LINKS)} (puckboard profiles show)"
        ) from None


def draw_timing(link: LinkTiming | str, rng: np.random.Generator) -> tuple[float, float]:
    """One (period, latency) in seconds drawn uniformly within ``link``'s ranges, as the
    link has them; a simulation rounds them to its whole steps
    (:meth:`puckboard.scenario.scene.Control.rounded`).

    Always two draws from ``rng`` (none skipped for a fixed range), so what is drawn
    after stays the same whichever link was drawn from.
    """
    if isinstance(link, str):
        link = get_link(link)
    u_period, u_latency = rng.random(2)
    period = link.period[0] + float(u_period) * (link.period[1] - link.period[0])
    latency = link.latency[0] + float(u_latency) * (link.latency[1] - link.latency[0])
    return period, latency
