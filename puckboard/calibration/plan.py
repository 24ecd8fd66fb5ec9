"""The plan of an IR calibration: where the robot stops, how it turns, how long it takes.

The robot starts touching a wall, facing it, so its centre is one body radius (the
profile's ``body_radius``) from the wall. It backs away in equal steps, measured by its
step counters, and at every stop turns in place through a full turn, pausing wherever
one of its eight sensors looks straight at the wall (:class:`Presentation`). A sensor
is only ever presented by turning the robot, never by moving the wall, so the whole run
needs nothing but a wall and a few centimetres of floor.

Two choices keep the robot's own errors out of the fit:

* **Each sensor straight at the wall.** Turned by minus its heading, a sensor looks
  perpendicular to the wall, where its response is at its highest and does not change
  to first order with the robot's heading: a turn that came out a few degrees wrong
  (wheels slip, the axle length is uncertain) changes the reading by well under a
  percent, where at 17° from the perpendicular it would change it by several.
* **Touching the wall again before each stop.** Turning in place on slipping wheels
  moves the robot a little, and over twenty full turns that adds up to millimetres (the
  response falls by 5 to 19 % per mm, by Webots' table). So
  before each stop the robot drives forward until it touches the wall again (a few mm
  beyond, which its wheels slip through), where its distance is known once more, and
  backs from there to the stop: each stop carries the errors of one turn and one move
  only.

Successive stops turn alternately one way and the other, so the heading the step counters
count stays within one turn of the start.

The speeds are fractions of the profile's wheel speed limit, so a plan for an e-puck1
(1000 steps/s) is as gentle as one for an e-puck2 (1100): turning at 30 % and driving at
15 % of the limit keeps well clear of the firmware's clamp and makes each move a few
control periods long even over a slow link. The duration is estimated from them and the
readings' timing; it leaves out the link's own latency, so a real run takes a little longer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..profile import RobotProfile
from ..records import PROX_NAMES
from ..sim.ir_models import ir_model

__all__ = [
    "DEFAULT_DISTANCE",
    "DEFAULT_SAMPLES",
    "DEFAULT_SAMPLE_PERIOD",
    "DEFAULT_STEP",
    "DRIVE_FRACTION",
    "MAX_DISTANCE",
    "PUSH_FRACTION",
    "PUSH_MARGIN",
    "TURN_FRACTION",
    "CalibrationPlan",
    "Presentation",
    "make_plan",
]

#: How far the robot backs away from touching (m): at 6 cm more the front sensors are
#: 9 cm from the wall, beyond the 7 cm where the response table ends.
DEFAULT_DISTANCE = 0.06
#: Distance between stops (m): 21 stops over 6 cm, five of them in the steep first 1.5 cm.
DEFAULT_STEP = 0.003
#: Readings averaged at each pose.
DEFAULT_SAMPLES = 10
#: Seconds between readings: the e-puck2 firmware refreshes its IR values at 20 Hz in
#: its slow mode (100 Hz in the fast one), so readings this far apart are new ones.
DEFAULT_SAMPLE_PERIOD = 0.05
#: The farthest a plan may back away (m): beyond, every sensor reads nothing.
MAX_DISTANCE = 0.15
#: How far beyond touching the robot drives when it touches the wall again (m), plus
#: :data:`PUSH_FRACTION` of the way back: enough for a believed wheel radius a few
#: percent off the true one (sources give 20 to 20.5 mm) to still reach the wall.
PUSH_MARGIN = 0.002
PUSH_FRACTION = 0.05
#: Wheel speeds of the moves, as fractions of the profile's limit (see the docstring).
TURN_FRACTION = 0.30
DRIVE_FRACTION = 0.15


@dataclass(frozen=True)
class Presentation:
    """One pose of a stop: the robot turned ``heading`` (rad, counter-clockwise from
    facing the wall) so that ``sensors`` look at the wall."""

    name: str
    heading: float
    sensors: tuple[str, ...]


@dataclass(frozen=True)
class CalibrationPlan:
    """What the robot will do; see the module docstring. Distances in m, speeds rad/s."""

    profile: RobotProfile
    backs: tuple[float, ...]  # how far from touching each stop is (m), the first 0
    presentations: tuple[Presentation, ...]  # by increasing turn from facing the wall
    samples: int
    sample_period: float  # s between readings
    settle: float  # s waited after each move before reading
    turn_speed: float  # wheel rad/s while turning (opposite on the two wheels)
    drive_speed: float  # wheel rad/s while driving to and from the wall

    @property
    def start_distance(self) -> float:
        """Robot centre to wall when touching it (m): one body radius."""
        return self.profile.body_radius

    @property
    def stops(self) -> int:
        return len(self.backs)

    @property
    def turn_rate(self) -> float:
        """The body's rate while turning in place (rad/s)."""
        p = self.profile
        return 2.0 * self.turn_speed * p.wheel_radius / p.axle_length

    @property
    def drive_rate(self) -> float:
        """The body's speed while driving to and from the wall (m/s)."""
        return self.drive_speed * self.profile.wheel_radius

    def push(self, backed: float) -> float:
        """How far beyond touching (m) the robot drives when it touches the wall again
        from ``backed`` m away."""
        return PUSH_MARGIN + PUSH_FRACTION * backed

    def pose_seconds(self) -> float:
        """Seconds spent reading at one pose (settling included)."""
        return self.settle + self.samples * self.sample_period

    def duration(self, stops: int | None = None) -> float:
        """Estimated seconds for the whole run, or for its first ``stops`` stops (moves at
        full speed, no link latency). Later stops take longer than earlier ones (each
        drives back to the wall and out further), which is why the time left is told
        from this model and not from the seconds per pose so far."""
        k = self.stops if stops is None else max(0, min(stops, self.stops))
        if k == 0:
            return 0.0
        reading = 1 + k * len(self.presentations)  # the first, facing the wall
        turning = k * math.tau - (math.tau - self.presentations[-1].heading) * (k == self.stops)
        driving = sum(
            2 * self.push(before) + before + back if j else back
            for j, (before, back) in enumerate(zip((0.0, *self.backs[:k]), self.backs[:k]))
        )
        return (
            reading * self.pose_seconds()
            + turning / self.turn_rate
            + driving / self.drive_rate
            + (k - 1) * self.settle  # after each touch
        )

    def targets(self, stop: int) -> tuple[list[tuple[float, Presentation]], float]:
        """The headings (rad, cumulative) of stop ``stop``'s poses in the order visited, and
        the heading it ends at, facing the wall again: even stops turn from 0 to 2π,
        odd ones back from 2π to 0."""
        if stop % 2 == 0:
            return [(p.heading, p) for p in self.presentations], math.tau
        return [(p.heading, p) for p in reversed(self.presentations)], 0.0

    def describe(self) -> str:
        """The plan as ``--dry-run`` prints it."""
        p = self.profile
        mm = 1000.0
        step = self.backs[1] - self.backs[0] if self.stops > 1 else 0.0
        lines = [
            f"robot: {p.name} (body radius {p.body_radius * mm:g} mm, wheels "
            f"{p.wheel_radius * mm:g} mm, axle {p.axle_length * mm:g} mm)",
            f"start: touching a white wall, facing it (centre {self.start_distance * mm:g} mm "
            "from the wall)",
            f"{self.stops} stops, {self.backs[0] * mm:g} to {self.backs[-1] * mm:g} mm back "
            f"from touching in {step * mm:g} mm steps (centre "
            f"{(self.start_distance + self.backs[0]) * mm:g} to "
            f"{(self.start_distance + self.backs[-1]) * mm:g} mm from the wall)",
            "before each stop the robot touches the wall again, then backs to the stop",
            "at each stop a full turn in place (alternately left and right), pausing with each "
            "sensor",
            "straight at the wall:",
        ]
        half = (len(self.presentations) + 1) // 2
        for part in (self.presentations[:half], self.presentations[half:]):
            poses = (f"{p.name} {math.degrees(p.heading):.0f}°" for p in part)
            lines.append("  " + ", ".join(poses))
        lines += [
            f"{self.samples} readings per pose, {self.sample_period:g} s apart, after "
            f"{self.settle:g} s to settle",
            f"speeds: turning {self.turn_speed:.2f} rad/s per wheel "
            f"({math.degrees(self.turn_rate):.0f}°/s in place), driving "
            f"{self.drive_speed:.2f} rad/s ({self.drive_rate * mm:.1f} mm/s)",
            f"expected duration: about {_minutes(self.duration())} (plus the link's latency)",
            f"space needed: the wall, and {(self.backs[-1] + 2 * p.body_radius + 0.05) * 100:.0f}"
            " cm of flat floor in front of it",
        ]
        return "\n".join(lines)


def _minutes(seconds: float) -> str:
    whole = int(round(seconds))
    minutes, rest = divmod(whole, 60)
    return f"{minutes} min {rest:02d} s" if minutes else f"{rest} s"


def _presentations(profile: RobotProfile) -> tuple[Presentation, ...]:
    """The poses that put each sensor straight in front of the wall: the robot turned by
    minus the sensor's heading, in increasing turns from facing the wall."""
    out = [
        Presentation(name, (-pose.heading) % math.tau, (name,))
        for name, pose in zip(PROX_NAMES, profile.prox_poses)
    ]
    return tuple(sorted(out, key=lambda p: p.heading))


def make_plan(
    profile: RobotProfile,
    *,
    distance: float = DEFAULT_DISTANCE,
    step: float = DEFAULT_STEP,
    samples: int = DEFAULT_SAMPLES,
    sample_period: float = DEFAULT_SAMPLE_PERIOD,
) -> CalibrationPlan:
    """The plan for ``profile``: back ``distance`` (m) in steps of ``step`` (m), reading
    ``samples`` times, ``sample_period`` s apart, at each pose. A ``ValueError`` (one
    line naming the number) for a plan that cannot work."""
    model = ir_model(profile.prox_model)
    if not model.has_response:
        raise ValueError(
            f"profile {profile.name!r} senses with {model.summary}: it has no IR response "
            "to calibrate; calibrate a physical e-puck (epuck, e-puck1)"
        )
    if not (math.isfinite(distance) and 0 < distance <= MAX_DISTANCE):
        raise ValueError(
            f"distance must be more than 0 and at most {MAX_DISTANCE * 1000:g} mm, got "
            f"{distance * 1000:g} mm"
        )
    if not (math.isfinite(step) and 0.0005 <= step <= distance):
        raise ValueError(
            f"step must be at least 0.5 mm and at most the distance ({distance * 1000:g} mm), "
            f"got {step * 1000:g} mm"
        )
    if samples < 2:
        raise ValueError(f"samples must be at least 2 (their spread weighs the fit), got {samples}")
    if not (math.isfinite(sample_period) and 0 < sample_period <= 2.0):
        raise ValueError(f"sample period must be more than 0 and at most 2 s, got {sample_period}")
    count = int(math.floor(distance / step + 1e-9)) + 1
    backs = tuple(round(k * step, 9) for k in range(count))
    limit = profile.max_wheel_speed
    return CalibrationPlan(
        profile=profile,
        backs=backs,
        presentations=_presentations(profile),
        samples=int(samples),
        sample_period=float(sample_period),
        settle=2.0 * float(sample_period),
        turn_speed=TURN_FRACTION * limit,
        drive_speed=DRIVE_FRACTION * limit,
    )
