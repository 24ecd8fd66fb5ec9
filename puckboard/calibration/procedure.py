"""The calibration run: move the robot through the plan and read its sensors at every pose.

The robot is any :class:`~puckboard.backends.base.RobotAdapter` that reports its IR values
and step counters: a real e-puck (``EPuckReal``, over Wi-Fi or sercom), the emulated one,
or a simulated one in tests. Where the robot is comes from its step counters alone
(:class:`Odometry`, with the profile's wheels and axle), as it must on a real robot; a
move runs until the counters say it is done, re-sending its command every poll so the
adapter's command watchdog never stops it half way, and slowing down as it nears its
target, as much as the link's latency needs, so that it stops close to where it was meant
to. Where exactly it stopped is read again afterwards: the fit uses the pose the counters
give, not the one that was aimed at.

At each pose the robot stands still for the plan's settling time and then takes the
plan's number of readings. What the run keeps per pose (:class:`PoseReading`) is the mean
and spread of each sensor's values, how many of them were clipped at 0 or at full scale
(a clipped mean is not the response), and the ambient light where the backend reports it.

Safety: the wheels are commanded to zero whatever ends the run (the end, an error, a
check that failed, Ctrl-C), and every move has a deadline. Checks that find a run that
cannot work stop it at once with a :class:`~puckboard.errors.CalibrationError` saying what
to fix (:mod:`.checks`).

Time: on a real robot the waits are wall-clock seconds. A simulated robot in a stepped
world (the embedded or fake backend) is stepped instead, the same seconds of its time,
so tests run as fast as the simulator goes and come out the same every time.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Protocol

import numpy as np
import numpy.typing as npt

from ..backends.base import RobotAdapter, Stepper
from ..errors import CalibrationError
from ..ir_response import RAW_MAX
from ..profile import RobotProfile
from ..records import Sensor
from . import checks
from .plan import CalibrationPlan, Presentation
from .readings import Measurements, PoseReading, Progress
from .response import WallModel

if TYPE_CHECKING:
    from ..backends.base import RobotAdapter

__all__ = ["CalibrationInterrupted", "Odometry", "run_calibration"]

log = logging.getLogger(__name__)

FloatArray = npt.NDArray[np.float64]

#: A move whose step counters have not changed after this long (s) is a robot whose
#: wheels do not turn.
STALL_S = 1.0
#: A move may take this many times its expected duration, plus :data:`MOVE_SLACK_S`.
MOVE_FACTOR = 3.0
MOVE_SLACK_S = 2.0
#: The slowest a move goes, as a fraction of its speed: about 3 steps/s while turning.
MIN_SCALE = 0.01
#: Near its target a move goes at most this fraction of the remaining way in one poll.
APPROACH = 0.7
#: Close enough: headings within 0.5°, distances within 0.2 mm (the pose is read again
#: afterwards, and the fit uses that).
TURN_TOLERANCE = math.radians(0.5)
DRIVE_TOLERANCE = 0.0002
#: Longest wait between two polls of a move (s).
MAX_POLL_S = 0.02


class _Clock(Protocol):
    def now(self) -> float: ...

    def sleep(self, seconds: float) -> None: ...


class _WallClock:
    """A real robot's time."""

    def now(self) -> float:
        return time.monotonic()

    def sleep(self, seconds: float) -> None:
        time.sleep(seconds)


class _SteppedClock:
    """A simulated robot's time: waiting is stepping its world (at least one step)."""

    def __init__(self, stepper: Stepper) -> None:
        self.stepper = stepper

    def now(self) -> float:
        return float(self.stepper.time)

    def sleep(self, seconds: float) -> None:
        self.stepper.step(max(1, int(round(seconds / self.stepper.dt))))


class Odometry:
    """Dead reckoning from the wheel encoders with ``profile``'s wheels and axle.

    The frame is the start pose: x towards the wall, heading counter-clockwise and
    cumulative (a full turn is 2π, not 0), so the plan's headings are reached without
    ambiguity. ``backed`` is how far the centre moved away from the wall.
    """

    def __init__(self, profile: RobotProfile) -> None:
        self.radius = profile.wheel_radius
        self.axle = profile.axle_length
        self.x = 0.0
        self.y = 0.0
        self.theta = 0.0
        self.encoders: tuple[float, float] | None = None

    @property
    def backed(self) -> float:
        return -self.x

    def update(self, left: float, right: float) -> None:
        """The encoders now read ``left``, ``right`` (rad since the adapter opened)."""
        if self.encoders is not None:
            dl = (left - self.encoders[0]) * self.radius
            dr = (right - self.encoders[1]) * self.radius
            ds = 0.5 * (dl + dr)
            dtheta = (dr - dl) / self.axle
            mid = self.theta + 0.5 * dtheta
            self.x += ds * math.cos(mid)
            self.y += ds * math.sin(mid)
            self.theta += dtheta
        self.encoders = (left, right)


class _Run:
    """One run of a plan on one robot (see the module docstring)."""

    def __init__(
        self,
        adapter: RobotAdapter,
        plan: CalibrationPlan,
        model: WallModel,
        clock: _Clock,
        progress: Callable[[Progress], None] | None,
    ) -> None:
        self.adapter = adapter
        self.plan = plan
        self.model = model
        self.clock = clock
        self.progress = progress
        self.odometry = Odometry(plan.profile)
        self.poll = min(MAX_POLL_S, plan.sample_period)
        self.readings: list[PoseReading] = []
        self.per_poll: dict[bool, float] = {}  # by turn (True) or drive: see _move
        self.t0 = clock.now()
        missing = {Sensor.PROXIMITY, Sensor.ENCODERS} - adapter.available_sensors
        if missing:
            raise CalibrationError(
                f"the {adapter.backend_name} backend does not report "
                f"{' or '.join(sorted(s.value for s in missing))}; calibrate ir needs both"
            )
        adapter.enable(Sensor.PROXIMITY, Sensor.ENCODERS)
        self.has_light = Sensor.LIGHT in adapter.available_sensors
        if self.has_light:
            adapter.enable(Sensor.LIGHT)

    # -- reading ---------------------------------------------------------------------------
    def read(self) -> tuple[FloatArray, FloatArray | None]:
        """One reading: IR values and ambient light (or None); the odometry follows."""
        records = self.adapter.sense_all()
        encoders = records[Sensor.ENCODERS]
        self.odometry.update(float(encoders.left), float(encoders.right))
        raw = np.array(records[Sensor.PROXIMITY].raw, dtype=float)
        light = records.get(Sensor.LIGHT)
        return raw, (np.array(light.raw, dtype=float) if light is not None else None)

    def sample(self, stop: int, presentation: Presentation) -> PoseReading:
        """Stand still, then read the plan's number of times."""
        plan = self.plan
        self.clock.sleep(plan.settle)
        values, ambient = [], []
        start = self.clock.now()
        for k in range(plan.samples):
            if k:  # readings sample_period apart, however long each exchange takes
                self.clock.sleep(max(0.0, start + k * plan.sample_period - self.clock.now()))
            raw, light = self.read()
            values.append(raw)
            if light is not None:
                ambient.append(light)
        v = np.array(values)
        odo = self.odometry
        return PoseReading(
            stop=stop,
            pose=presentation.name,
            sensors=presentation.sensors,
            backed=odo.backed,
            distance=plan.start_distance + odo.backed,
            heading=odo.theta,
            mean=v.mean(axis=0),
            std=v.std(axis=0, ddof=1),
            samples=plan.samples,
            low=(v <= 0.0).sum(axis=0).astype(np.int64),
            high=(v >= RAW_MAX).sum(axis=0).astype(np.int64),
            ambient=np.array(ambient).mean(axis=0) if ambient else None,
            time=self.clock.now() - self.t0,
        )

    # -- moving ----------------------------------------------------------------------------
    def turn_to(self, heading: float) -> None:
        self._move(lambda: heading - self.odometry.theta, turn=True)

    def back_to(self, backed: float) -> None:
        self._move(lambda: backed - self.odometry.backed, turn=False)

    def touch(self) -> None:
        """Drive forward until touching the wall again, and a little beyond (the wheels
        slip against it), and take up the count there: touching, the centre is one body
        radius from the wall (see :mod:`.plan`)."""
        target = -self.plan.push(self.odometry.backed)
        # never backwards: wheels that ran on into the wall slipped there, and driving
        # them back would take the robot away from the wall by as much
        self._move(lambda: target - self.odometry.backed, turn=False, reverse=False)
        self.clock.sleep(self.plan.settle)
        self.read()
        self.odometry.x = 0.0

    def _move(self, remaining: Callable[[], float], *, turn: bool, reverse: bool = True) -> None:
        """Drive until ``remaining()`` (rad or m still to go, by the step counters) is
        within tolerance: a turn counter-clockwise for a positive remainder, away from the
        wall for a positive one; an overshoot is driven back (unless not ``reverse``:
        then it ends the move).

        The speed is proportional to what remains, so that one poll covers at most
        :data:`APPROACH` of it: how far one poll carries the robot at full speed is learnt
        as the run goes (the largest seen), since it depends on the link's latency. A slow
        link (a poll of 0.1 s over Bluetooth) then stops as precisely as a fast one, only
        later.
        Raises :class:`CalibrationError` for wheels that do not turn and for a move that
        does not finish in time."""
        plan = self.plan
        full, rate = (
            (plan.turn_speed, plan.turn_rate) if turn else (plan.drive_speed, plan.drive_rate)
        )
        tolerance = TURN_TOLERANCE if turn else DRIVE_TOLERANCE
        first = remaining()
        if abs(first) <= tolerance:
            return
        start = self.clock.now()
        deadline = start + MOVE_FACTOR * abs(first) / rate + MOVE_SLACK_S
        assert self.odometry.encoders is not None
        enc0 = self.odometry.encoders
        one_step = self.adapter.profile.rad_per_step
        # travel of one poll at full speed: a first guess, then the largest seen on this link
        per_poll = self.per_poll.get(turn, rate * self.poll)
        previous, scale, before = first, 0.0, 0.0
        while True:
            left = remaining()
            if abs(left) <= tolerance or (not reverse and left * first < 0):
                break
            if scale:
                # what moved it since the last poll: the last command, or (the link being
                # slow) still the one before it
                per_poll = max(per_poll, abs(previous - left) / max(scale, before))
                self.per_poll[turn] = per_poll
            before = scale
            scale = min(1.0, max(MIN_SCALE, APPROACH * abs(left) / per_poll))
            w = math.copysign(full * scale, left)
            self.adapter.set_wheel_speeds(*((-w, w) if turn else (-w, -w)))
            previous = left
            self.clock.sleep(self.poll)
            self.read()
            now = self.clock.now()
            enc = self.odometry.encoders
            if now - start > STALL_S and all(abs(a - b) < one_step for a, b in zip(enc, enc0)):
                self.adapter.stop_wheels()
                raise CalibrationError(
                    f"the wheels do not turn: the step counters stayed at "
                    f"{enc[0]:.3f}, {enc[1]:.3f} rad for {now - start:.1f} s of commanding a "
                    f"{'turn' if turn else 'move'}; switch the motors on (an e-puck2 over Wi-Fi "
                    "needs selector 15), charge the battery, and start again"
                )
            if now > deadline:
                self.adapter.stop_wheels()
                still = remaining()
                what = (
                    f"turn ({math.degrees(still):.0f}° still to go)"
                    if turn
                    else f"move ({still * 1000:.1f} mm still to go)"
                )
                raise CalibrationError(
                    f"the robot did not finish a {what} in {now - start:.1f} s: its wheels "
                    "turn too slowly or the link is too slow; charge the battery and check "
                    "the connection"
                )
        self.adapter.stop_wheels()

    # -- the whole run ---------------------------------------------------------------------
    def run(self) -> None:
        plan = self.plan
        total = 1 + plan.stops * len(plan.presentations)
        self.read()  # the first encoder values: odometry starts here
        start = Presentation("facing", 0.0, ("front_right", "front_left"))
        self._report(0, start, total)
        self.readings.append(self.sample(0, start))
        checks.wall_seen(self.readings[0], self.model)
        for stop, backed in enumerate(plan.backs):
            if stop:
                self.touch()
                self.back_to(backed)
            poses, end = plan.targets(stop)
            for heading, presentation in poses:
                self.turn_to(heading)
                self._report(stop, presentation, total)
                reading = self.sample(stop, presentation)
                self.readings.append(reading)
                if stop and presentation is plan.presentations[0]:
                    checks.moving_away(self._first(presentation), reading, self.model)
            if stop == 0:
                checks.sensors_respond(self.readings, self.model)
            if stop < plan.stops - 1:
                self.turn_to(end)

    def _first(self, presentation: Presentation) -> PoseReading:
        """The reading of ``presentation`` at the first stop, touching the wall."""
        return next(r for r in self.readings if r.stop == 0 and r.pose == presentation.name)

    def _report(self, stop: int, presentation: Presentation, total: int) -> None:
        if self.progress is not None:
            self.progress(
                Progress(
                    stop=stop,
                    stops=self.plan.stops,
                    backed=self.odometry.backed,
                    pose=presentation.name,
                    sensors=presentation.sensors,
                    done=len(self.readings),
                    total=total,
                )
            )


class CalibrationInterrupted(KeyboardInterrupt):
    """Ctrl-C during a run, carrying what was measured until then (``measurements``):
    every stop measured is kept, for a fit of what there is, instead of thrown away."""

    def __init__(self, measurements: Measurements) -> None:
        super().__init__("interrupted")
        self.measurements = measurements


def run_calibration(
    adapter: RobotAdapter,
    plan: CalibrationPlan,
    model: WallModel,
    *,
    progress: Callable[[Progress], None] | None = None,
) -> Measurements:
    """Run ``plan`` on ``adapter``'s robot and return what it read at every pose.

    The robot must start touching a wall, facing it. ``model`` is the plan's profile's
    :class:`~.response.WallModel` (the checks compare readings with it). ``progress`` is
    told before each pose is read. The wheels are stopped however the run ends; a step
    that cannot work raises :class:`~puckboard.errors.CalibrationError`.
    """
    stepper = adapter.stepper
    clock: _Clock = _SteppedClock(stepper) if stepper is not None else _WallClock()
    run = _Run(adapter, plan, model, clock, progress)

    def measured() -> Measurements:
        return Measurements(
            plan=plan,
            readings=tuple(run.readings),
            seconds=clock.now() - run.t0,
            backend=adapter.backend_name,
        )

    try:
        run.run()
    except KeyboardInterrupt as exc:
        _stop_wheels(adapter)
        raise CalibrationInterrupted(measured()) from exc
    finally:
        _stop_wheels(adapter)
    return measured()


def _stop_wheels(adapter: RobotAdapter) -> None:
    """Zero the wheels, best effort: after a lost link there is nobody to tell (the
    adapter already tried), and the error that ended the run is the one to report."""
    if adapter.closed:
        return
    try:
        adapter.stop_wheels()
    except Exception as exc:
        log.warning("robot %r: could not stop the wheels: %s", adapter.name, exc)
