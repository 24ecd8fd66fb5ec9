"""One trial: a simulation with the three odometry estimates running side by side.

The estimates share the simulation, so their errors differ only by what each one
knows (the step counters, the gyro, a wrong axle length), never by the run. Every
estimate starts at the true start pose and is compared with the ground truth read in the
same sensing pass; the package docstring says what each estimate stands for.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ...blackboard import Snapshot
from ...estimation.odometry import OdometryFilter, wrap_angle
from ...estimation.sources import OdometrySource
from ...profile import RobotProfile
from ...records import Sensor

if TYPE_CHECKING:
    from ...behaviours.presets import ControllerFactory
    from ...control.episode import Episode

__all__ = ["CHI2_95_2DOF", "VARIANTS", "Trace", "four_digits", "run_case"]

CHI2_95_2DOF = 5.991  # position error inside the 95 % ellipse when d² is below this
VARIANTS = ("encoders", "encoders + gyro", "axle +1 mm")


@dataclass
class Trace:
    """One robot's estimate and truth over a run, for one variant."""

    robot: str
    variant: str
    t: list[float] = field(default_factory=list)
    est: list[tuple[float, float, float]] = field(default_factory=list)
    truth: list[tuple[float, float, float]] = field(default_factory=list)
    cov: list[npt.NDArray[np.float64]] = field(default_factory=list)

    def add(self, t: float, est: Any, truth: Any, cov: npt.NDArray[np.float64]) -> None:
        self.t.append(t)
        self.est.append((float(est[0]), float(est[1]), float(est[2])))
        self.truth.append((float(truth[0]), float(truth[1]), float(truth[2])))
        self.cov.append(np.array(cov[:2, :2], copy=True))

    def metrics(self) -> dict[str, float]:
        est = np.array(self.est)
        truth = np.array(self.truth)
        pos = np.hypot(est[:, 0] - truth[:, 0], est[:, 1] - truth[:, 1])
        head = np.abs(np.remainder(est[:, 2] - truth[:, 2] + math.pi, math.tau) - math.pi)
        travelled = float(np.hypot(*np.diff(truth[:, :2], axis=0).T).sum())
        inside = []
        for k in range(len(pos)):
            e = est[k, :2] - truth[k, :2]
            cov = self.cov[k]
            if np.linalg.det(cov) <= 1e-24:
                inside.append(pos[k] < 1e-6)  # a point estimate is right only if exact
            else:
                inside.append(float(e @ np.linalg.solve(cov, e)) < CHI2_95_2DOF)
        return {
            "final_position_error_m": float(pos[-1]),
            "max_position_error_m": float(pos.max()),
            "final_heading_error_deg": math.degrees(float(head[-1])),
            "max_heading_error_deg": math.degrees(float(head.max())),
            "distance_m": travelled,
            "error_per_metre": float(pos[-1] / travelled) if travelled > 0 else 0.0,
            "final_position_sd_m": float(math.sqrt(max(np.trace(self.cov[-1]), 0.0))),
            "inside_95_fraction": float(np.mean(inside)),
        }


class _GyroOdometrySource(OdometrySource):
    """:class:`OdometrySource` fused with the gyro, writing under ``estimate/gyro/`` so it
    runs next to the encoder-only one on the same blackboard."""

    writes = ("estimate/gyro/pose", "estimate/gyro/pose_cov", "estimate/gyro/slip")

    def compute(self, inputs: Snapshot) -> dict[str, Any]:
        out = super().compute(inputs) or {}
        return {"estimate/gyro/" + k.removeprefix("estimate/"): v for k, v in out.items()}


def run_case(
    scene_name: str,
    wheel_noise: float,
    seed: int,
    *,
    steps: int | None = None,
    laps: float | None = None,
    controller: str | ControllerFactory | None = None,
    gyro_noise: float = 0.0,
    gyro_bias: float = 0.0,
    settle: float = 0.0,
) -> tuple[dict[str, Any], list[Trace]]:
    """One simulation with the three estimates of the package docstring side by side.

    ``laps`` stops the run once every robot has turned through that many full turns
    (a lap of a closed loop track); otherwise the run lasts the scene's whole duration
    (for the two-robot pass: meeting, passing, both obstacles and back on the line).
    ``steps`` caps the control cycles; ``controller`` replaces every robot's controller
    (default: the scene's). ``gyro_noise`` and ``gyro_bias`` are the simulated gyro's σ
    and offset (rad/s; at 0 the run is the same as without a gyro). ``settle`` (s): the
    robots first stand still that long with the estimates running, as a robot waits on
    the table before it starts; that is when the gyro's offset is learned. Returns the
    per-robot metrics and the traces.
    """
    from ...control.episode import Episode

    overrides = {
        # odometry and gyro fusion are about the physical robot (its e-puck2 gyro): the
        # thesis's scenes default to V-REP's model, which has no gyro
        "robot.profile": "epuck",
        "noise.wheel_speed": wheel_noise,
        "noise.gyro": gyro_noise,
        "noise.gyro_bias": gyro_bias,
    }
    episode = Episode(scene_name, seed=seed, controller=controller, overrides=overrides)
    world = episode.world
    if world is None:  # pragma: no cover - the embedded backend always has one
        raise RuntimeError("the estimation benchmark needs the embedded simulator")
    names = list(world.robot_names)
    loop = episode.loop
    dt = loop.period
    sources: dict[str, OdometrySource] = {}
    gyro_sources: dict[str, OdometrySource] = {}
    shadows: dict[str, dict[str, OdometryFilter]] = {}
    last_enc: dict[str, tuple[float, float]] = {}
    turned = dict.fromkeys(names, 0.0)
    last_theta: dict[str, float] = {}
    traces = {(n, v): Trace(n, v) for n in names for v in VARIANTS}
    slips = dict.fromkeys(names, 0)
    for i, name in enumerate(names):
        adapter = episode.connection.adapters[name]
        profile: RobotProfile = adapter.profile
        x0, y0, theta0 = (float(v) for v in world.poses[i])
        start = (x0, y0, theta0)
        adapter.enable(Sensor.GYRO)  # off by default in the simulator; no effect on the run
        sources[name] = OdometrySource(initial=start, use_gyro=False).attach(loop, name)
        gyro_sources[name] = _GyroOdometrySource(initial=start).attach(loop, name)
        wrong = dataclasses.replace(profile, axle_length=profile.axle_length + 0.001)
        shadows[name] = {"axle +1 mm": OdometryFilter(wrong, initial=start)}
        last_theta[name] = start[2]

    def after_cycle(ep: Episode) -> None:
        for i, name in enumerate(names):
            ns = ep.connection.adapters[name].ns
            # (1) the blackboard estimate, against the truth read in the same sensing pass
            est_rec = ns.get("estimate/pose")
            truth = ns.get("pose").value
            cov = ns.value("estimate/pose_cov")
            t = est_rec.stamp
            traces[(name, "encoders")].add(t, _xyt(est_rec.value), _xyt(truth), cov)
            gyro_rec = ns.get("estimate/gyro/pose")
            traces[(name, "encoders + gyro")].add(
                t, _xyt(gyro_rec.value), _xyt(truth), ns.value("estimate/gyro/pose_cov")
            )
            slips[name] += bool(ns.value("estimate/slip"))
            # (2) the same encoders, miscalibrated filter
            enc = ns.get("encoders").value
            if name in last_enc:
                f = shadows[name]["axle +1 mm"]
                f.predict(enc.left - last_enc[name][0], enc.right - last_enc[name][1])
                traces[(name, "axle +1 mm")].add(t, f.state, _xyt(truth), f.cov)
            last_enc[name] = (enc.left, enc.right)
            now = world.poses[i]
            turned[name] += wrap_angle(float(now[2]) - last_theta[name])
            last_theta[name] = float(now[2])

    episode.add_observer(after_cycle)

    def done(_: Any) -> bool:
        return laps is not None and all(abs(v) >= laps * math.tau for v in turned.values())

    t0 = time.perf_counter()
    if settle > 0:  # standing still: sense and estimate, command nothing, step
        all_sources = [*sources.values(), *gyro_sources.values()]
        for _ in range(round(settle / dt)):
            for name in names:
                episode.connection.adapters[name].sense_all()
            for source in all_sources:
                source.step()
            world.step()
    duration = episode.scene.duration * (2.0 if laps is not None else 1.0)
    until = done if laps is not None else None
    try:
        if steps is not None:
            loop.run(cycles=steps, until=until)
        else:
            loop.run(duration, until=until)
    finally:
        episode.connection.close()
    wall = time.perf_counter() - t0
    episode.judge.finish()

    robots = []
    for i, name in enumerate(names):
        row: dict[str, Any] = {
            "robot": name,
            "laps_turned": round(abs(turned[name]) / math.tau, 3),
            "collisions": int(world.collisions[i]),
            "slip_flagged_s": round(slips[name] * dt, 3),
            "source_failures": sources[name].failures + gyro_sources[name].failures,
        }
        for variant in VARIANTS:
            row[variant] = {k: four_digits(v) for k, v in traces[(name, variant)].metrics().items()}
        robots.append(row)
    info = {
        "scene": scene_name if controller is None else f"{scene_name} ({controller})",
        "wheel_noise": wheel_noise,
        "gyro_noise": gyro_noise,
        "gyro_bias": gyro_bias,
        "gyro_bias_learned": {n: four_digits(gyro_sources[n].gyro_bias) for n in names},
        "settle_s": settle,
        "seed": seed,
        "sim_time_s": round(loop.time, 3),
        "judge": "success" if episode.judge.success else f"failure: {episode.judge.failure}",
        "cycles": loop.cycles,
        "wall_s": round(wall, 3),
        "robots": robots,
    }
    return info, list(traces.values())


def _xyt(pose: Any) -> tuple[float, float, float]:
    return (pose.x, pose.y, pose.theta)


def four_digits(v: float) -> float:
    """A reported figure, to four significant digits: what the comparison needs, and a
    report that stays readable."""
    return float(f"{v:.4g}")
