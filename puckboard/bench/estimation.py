"""How good is the odometry estimate? Measured against the simulator's ground truth.

``run_suite(steps)`` is the ``estimation`` suite of ``puckboard bench``: it runs the
two-robot pass (its whole 120 s) with the scene's controllers and with the stock
controllers (with which the two robots collide), and three laps of ``line-follow`` on the
embedded simulator, with and without wheel-speed noise, for a few seeds, and reports
per robot the position and heading error of the estimate at the end and at worst, and
how often the true pose lay inside the estimate's 95 % ellipse. Three estimates run
side by side on the very same simulation:

``encoders``
    the :class:`~puckboard.estimation.OdometrySource` end to end, on the blackboard,
    fed by the simulated step counters. As on a real e-puck, the stepper motors make
    exactly the commanded steps and the counters count them; how far the body actually
    moves differs by the wheels' slip on the floor (the scene's wheel-speed noise) and by
    contacts (a robot pushed along a wall or an obstacle while its wheels turn). Neither
    is visible to odometry: this is the drift students meet on a real robot.
``encoders + gyro``
    the same source fused with the simulated gyro (the e-puck2's), which measures how
    fast the body actually turned: slip and contacts that fool the counters do not fool
    it. The gyro is ideal unless ``gyro_noise`` (σ, rad/s) or ``gyro_bias`` (rad/s) is
    given; the source learns a bias only while the wheels stand still (``settle``), so
    without a standstill a bias goes straight into the heading.
``axle +1 mm``
    the encoder filter with an axle 1 mm longer than the simulated robot's (54 instead
    of 53 mm; published values range from 51 to 56.5 mm): an uncalibrated robot.

Every estimate starts at the true start pose (the start jitter is not counted as
odometry error) and is compared with the ground truth of the same instant.

Run it with ``puckboard bench --suite estimation`` (``--plot FILE`` also draws the
estimate against the truth with covariance ellipses; ``puckboard bench --help`` lists the
suite's other options).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import statistics
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ..blackboard import Snapshot
from ..estimation.odometry import OdometryFilter, wrap_angle
from ..estimation.proximity import ProximityFilter
from ..estimation.sources import OdometrySource
from ..profile import RobotProfile
from ..records import Sensor
from .timing import seconds_per_call

__all__ = ["SEEDS", "Trace", "plot_traces", "run_case", "run_suite"]

log = logging.getLogger(__name__)

SEEDS: tuple[int, ...] = (1, 2, 3)
WHEEL_NOISE: tuple[float, ...] = (0.0, 0.03)  # 0.03: the shipped scenes' setting
LAPS = 3.0
CHI2_95_2DOF = 5.991  # position error inside the 95 % ellipse when d² is below this
VARIANTS = ("encoders", "encoders + gyro", "axle +1 mm")
#: (scene, laps or None for the whole scene, controller or None for the scene's).
#: The stock controller makes the two robots collide: the case odometry cannot see.
CASES: tuple[tuple[str, float | None, str | None], ...] = (
    ("two-robot-pass", None, None),
    ("two-robot-pass", None, "stock"),
    ("line-follow", LAPS, None),
)
LINE_FOLLOW_CASES = tuple(case for case in CASES if case[0] == "line-follow")


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
    controller: Any = None,
    gyro_noise: float = 0.0,
    gyro_bias: float = 0.0,
    settle: float = 0.0,
) -> tuple[dict[str, Any], list[Trace]]:
    """One simulation with the three estimates of the module docstring running side by side.

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
    from ..control.episode import Episode

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

    def after_cycle(ep: Any) -> None:
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
            row[variant] = {k: _round(v) for k, v in traces[(name, variant)].metrics().items()}
        robots.append(row)
    info = {
        "scene": scene_name if controller is None else f"{scene_name} ({controller})",
        "wheel_noise": wheel_noise,
        "gyro_noise": gyro_noise,
        "gyro_bias": gyro_bias,
        "gyro_bias_learned": {n: _round(gyro_sources[n].gyro_bias) for n in names},
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


def _round(v: float) -> float:
    return float(f"{v:.4g}")


# -- the IR filter on the simulator's sensor model ------------------------------------------
def measure_proximity(
    gaps: Sequence[float] = (0.01, 0.02, 0.03, 0.04),
    *,
    noise: float = 0.05,
    seed: int = 1,
    steps: int = 400,
) -> list[dict[str, float]]:
    """A robot standing still in front of a wall: raw against filtered front IR distances.

    For each ``gap`` (m, from the front of the body to the wall) one noise-free world gives
    the true distance of the two front sensors and one world with relative IR noise
    ``noise`` gives ``steps`` noisy readings. Reported: σ and bias (m) of the raw and the
    filtered readings (after a 20-step warm-up), and the variance ratio.
    """
    from ..scenario.scene import Arena, Noise, RobotSpec, Scene
    from ..sim.world import World

    rows = []
    for gap in gaps:
        robot = RobotSpec("still", 0.5 - 0.037 - gap, 0.0, 0.0)
        arena = Arena(-0.5, -0.4, 0.5, 0.4)

        def world(sigma: float, robot: RobotSpec = robot, arena: Arena = arena) -> Any:
            scene = Scene("wall", robots=(robot,), arena=arena, noise=Noise(proximity=sigma))
            return World(scene, seed=seed)

        truth = world(0.0).prox_distance[0, [0, 7]].copy()
        noisy = world(noise)
        flt = ProximityFilter()
        raw, filtered = [], []
        for _ in range(steps):
            noisy.step()
            z = noisy.prox_distance[0]
            out = flt.update(z, noisy.dt)
            raw.append(z[[0, 7]])
            filtered.append(out[[0, 7]])
        raw_err = np.array(raw[20:]) - truth
        out_err = np.array(filtered[20:]) - truth
        rows.append(
            {
                "gap_m": gap,
                "true_distance_m": _round(float(truth.mean())),
                "raw_sd_m": _round(float(raw_err.std(axis=0).mean())),
                "filtered_sd_m": _round(float(out_err.std(axis=0).mean())),
                "raw_bias_m": _round(float(raw_err.mean())),
                "filtered_bias_m": _round(float(out_err.mean())),
                "variance_ratio": _round(
                    float(raw_err.var(axis=0).mean() / max(out_err.var(axis=0).mean(), 1e-30))
                ),
            }
        )
    return rows


# -- costs ---------------------------------------------------------------------------------
def _median_us(fn: Any, calls: int = 2000) -> float:
    return seconds_per_call(fn, calls) * 1e6


def measure_costs() -> dict[str, float]:
    """Per-call costs (median µs of 5 repeats) behind the choices in the docs."""
    from filterpy.kalman import KalmanFilter

    odo = OdometryFilter()
    prox = ProximityFilter()
    z = np.full(8, 0.03)
    kfs = []
    for _ in range(8):
        kf = KalmanFilter(dim_x=2, dim_z=1)
        kf.F = np.array([[1.0, 0.05], [0.0, 1.0]])
        kf.H = np.array([[1.0, 0.0]])
        kf.R *= 4e-6
        kf.Q = np.diag([1e-9, 1e-4])
        kfs.append(kf)

    def filterpy_eight() -> None:
        for kf in kfs:
            kf.predict()
            kf.update(0.03)

    vec = _VectorisedCV(8)
    return {
        "odometry_predict_us": _median_us(lambda: odo.predict(0.1, 0.12)),
        "proximity_python_8_sensors_us": _median_us(lambda: prox.update(z, 0.05)),
        "proximity_numpy_vectorised_8_sensors_us": _median_us(lambda: vec.update(z, 0.05)),
        "proximity_filterpy_8_sensors_us": _median_us(filterpy_eight, calls=300),
    }


class _VectorisedCV:
    """The proximity filter's equations vectorised with numpy, only to measure the cost
    of that alternative (no gating or range handling beyond what costs the same)."""

    def __init__(self, n: int, var_z: float = 4e-6, var_a: float = 0.01) -> None:
        self.d = np.full(n, 0.03)
        self.rate = np.zeros(n)
        self.p00 = np.full(n, var_z)
        self.p01 = np.zeros(n)
        self.p11 = np.full(n, 0.09)
        self.var_z, self.var_a = var_z, var_a

    def update(self, z: npt.NDArray[np.float64], dt: float) -> npt.NDArray[np.float64]:
        dt2 = dt * dt
        d = self.d + self.rate * dt
        a = self.p00 + 2 * dt * self.p01 + dt2 * self.p11 + self.var_a * dt2 * dt2 / 4
        b = self.p01 + dt * self.p11 + self.var_a * dt2 * dt / 2
        c = self.p11 + self.var_a * dt2
        s = a + self.var_z
        y = z - d
        restart = y * y > 16.0 * s
        k0, k1 = a / s, b / s
        self.d = np.where(restart, z, np.clip(d + k0 * y, 0.0, 0.05))
        self.rate = np.where(restart, 0.0, self.rate + k1 * y)
        self.p00 = np.where(restart, self.var_z, (1 - k0) * a)
        self.p01 = np.where(restart, 0.0, (1 - k0) * b)
        self.p11 = np.where(restart, 0.09, c - k1 * b)
        return self.d.copy()


# -- the suite -----------------------------------------------------------------------------
def run_suite(
    steps: int | None = None,
    seeds: Sequence[int] = SEEDS,
    *,
    gyro_noise: float = 0.0,
    gyro_bias: float = 0.0,
    settle: float = 0.0,
    cases: str | Sequence[tuple[str, float | None, str | None]] = CASES,
    plot: Path | None = None,
    plot_contact: Path | None = None,
) -> dict[str, Any]:
    """The ``estimation`` benchmark suite (see the module docstring).

    ``steps`` caps each run's control cycles (a quick smoke run); ``None`` runs the two-robot
    pass to its verdict and line-follow for three laps. ``gyro_noise``, ``gyro_bias``: the
    simulated gyro's σ and offset (rad/s); ``settle`` (s) of standing still first (see
    :func:`run_case`). ``cases``: which of :data:`CASES` to run, or ``"all"`` /
    ``"line-follow"`` (its three laps only: a quicker comparison of the estimates).
    ``plot`` draws line-follow (first seed) against the truth there; ``plot_contact`` draws
    the stock two-robot pass (a collision, last seed).
    """
    for name, value, low, high in (
        ("gyro_noise", gyro_noise, 0.0, 1.0),
        ("gyro_bias", gyro_bias, -1.0, 1.0),
        ("settle", settle, 0.0, 60.0),
    ):
        if not low <= value <= high:
            raise ValueError(f"{name} must lie in [{low}, {high}], got {value}")
    if isinstance(cases, str):
        named = {"all": CASES, "line-follow": LINE_FOLLOW_CASES}
        if cases not in named:
            raise ValueError(f"cases must be one of {sorted(named)}, got {cases!r}")
        cases = named[cases]
    runs = []
    for scene_name, laps, controller in cases:
        for noise in WHEEL_NOISE:
            for seed in seeds:
                info, _ = run_case(
                    scene_name,
                    noise,
                    seed,
                    steps=steps,
                    laps=laps,
                    controller=controller,
                    gyro_noise=gyro_noise,
                    gyro_bias=gyro_bias,
                    settle=settle,
                )
                runs.append(info)
    return {
        "seeds": list(seeds),
        "wheel_noise": list(WHEEL_NOISE),
        "gyro_noise": gyro_noise,
        "gyro_bias": gyro_bias,
        "settle_s": settle,
        "variants": list(VARIANTS),
        "summary": summarise(runs),
        "proximity": measure_proximity(),
        "costs": measure_costs(),
        "runs": runs,
        "plots": _draw_plots(seeds, steps, plot, plot_contact),
    }


def _draw_plots(
    seeds: Sequence[int], steps: int | None, plot: Path | None, plot_contact: Path | None
) -> list[str]:
    written = []
    if plot is not None:
        _, traces = run_case("line-follow", 0.03, seeds[0], steps=steps, laps=LAPS)
        keep = [t for t in traces if t.variant in VARIANTS]
        title = f"line-follow, 3 laps, wheel noise 3 %, seed {seeds[0]}"
        written.append(str(plot_traces(keep, plot, title=title)))
    if plot_contact is not None:
        seed = seeds[-1]
        _, traces = run_case("two-robot-pass", 0.03, seed, steps=steps, controller="stock")
        written.append(
            str(
                plot_traces(
                    [t for t in traces if t.variant == "encoders"],
                    plot_contact,
                    every=20.0,
                    title=(
                        f"two-robot pass, stock controllers (they collide), wheel noise 3 %, "
                        f"seed {seed}"
                    ),
                )
            )
        )
    return written


def summarise(runs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Median (and max) over seeds and robots, per scene × wheel noise × variant."""
    groups: dict[tuple[str, float, str], list[dict[str, float]]] = {}
    for run in runs:
        for robot in run["robots"]:
            for variant in VARIANTS:
                groups.setdefault((run["scene"], run["wheel_noise"], variant), []).append(
                    robot[variant]
                )
    rows = []
    for (scene, noise, variant), ms in groups.items():
        row: dict[str, Any] = {
            "scene": scene,
            "wheel_noise": noise,
            "variant": variant,
            "n": len(ms),
        }
        for key in (
            "final_position_error_m",
            "final_heading_error_deg",
            "max_position_error_m",
            "distance_m",
            "inside_95_fraction",
        ):
            values = [m[key] for m in ms]
            row[key] = _round(statistics.median(values))
            if key == "inside_95_fraction":
                row[key + "_min"] = _round(min(values))
            else:
                row[key + "_max"] = _round(max(values))
        rows.append(row)
    return rows


# -- the plot ------------------------------------------------------------------------------
def plot_traces(
    traces: Sequence[Trace], path: str | Path, *, every: float = 30.0, title: str = ""
) -> Path:
    """Estimated against true paths, with 2σ position ellipses every ``every`` s (top), and
    the position error over time against the estimate's own 2σ (bottom).

    One column per trace. matplotlib is imported here (the ``viz`` extra); the figure is
    written to ``path`` (its suffix picks the format).
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.patches import Ellipse

    n = len(traces)
    fig, axes = plt.subplots(
        2, n, figsize=(5.0 * n, 7.2), squeeze=False, gridspec_kw={"height_ratios": [3, 1.4]}
    )
    for col, trace in enumerate(traces):
        ax, ax_err = axes[0][col], axes[1][col]
        truth = np.array(trace.truth)
        est = np.array(trace.est)
        t = np.array(trace.t)
        ax.plot(truth[:, 0], truth[:, 1], color="black", lw=1.2, label="truth (simulator)")
        ax.plot(est[:, 0], est[:, 1], color="tab:red", lw=0.9, ls="--", label="estimate")
        next_t = every
        for k, tk in enumerate(t):
            if tk + 1e-9 < next_t:
                continue
            next_t = tk + every
            vals, vecs = np.linalg.eigh(trace.cov[k])
            vals = np.clip(vals, 0.0, None)
            angle = math.degrees(math.atan2(vecs[1, 1], vecs[0, 1]))
            ax.add_patch(
                Ellipse(
                    (est[k, 0], est[k, 1]),
                    width=4 * math.sqrt(vals[1]),
                    height=4 * math.sqrt(vals[0]),
                    angle=angle,
                    fill=False,
                    color="tab:blue",
                    lw=0.8,
                )
            )
            ax.plot(est[k, 0], est[k, 1], ".", color="tab:red", ms=3)
            ax.plot(truth[k, 0], truth[k, 1], ".", color="black", ms=3)
        m = trace.metrics()
        ax.set_title(
            f"{trace.robot}: {trace.variant}\nfinal error {m['final_position_error_m'] * 100:.1f} cm, "
            f"{m['final_heading_error_deg']:.1f}° after {m['distance_m']:.1f} m",
            fontsize=9,
        )
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.grid(True, lw=0.3)
        error = np.hypot(est[:, 0] - truth[:, 0], est[:, 1] - truth[:, 1])
        two_sd = 2 * np.sqrt([max(np.trace(c), 0.0) for c in trace.cov])
        ax_err.fill_between(t, 0, two_sd, color="tab:blue", alpha=0.15, label="estimate's 2σ")
        ax_err.plot(t, error, color="tab:red", lw=1.0, label="position error")
        ax_err.set_xlabel("time (s)")
        ax_err.set_ylabel("m")
        ax_err.grid(True, lw=0.3)
    axes[0][0].plot([], [], color="tab:blue", lw=0.8, label=f"2σ ellipse every {every:g} s")
    axes[0][0].legend(loc="upper left", fontsize=7)
    axes[1][0].legend(loc="upper left", fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    out = Path(path)
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out
