"""Measure how close a dark obstacle is before a physical e-puck's IR sees it, against how
far the robot drives before its wheels act on that sight over each real link: the
physical argument of docs/controllers.md ("A black obstacle, against the link").

::

    python docs/measure_dark_obstacles.py

1. **First sight.** One shipped physical e-puck drives straight at a 6 cm cylinder (the
   shipped scenes' obstacles) at ``robust``'s speed, 2 ms steps, no noise, the cylinder
   dead ahead and 1 cm off its axis; the gap between body and cylinder when a front sensor
   first reads something (less than the 5 cm range), for reflectances from 1 down to the
   reality-gap range's 0.038.
2. **Reaction.** For each real link, runs drawn as ``--variation reality-gap`` draws them
   (period in the link's range, share of repeated readings in its range, each command's
   latency from its distribution, 50 ms steps, :class:`puckboard.sim.link_cycles.LinkCycleState`):
   the time from an instant uniformly within a cycle (the obstacle coming into range) to
   the wheels acting on the first new reading after it, times the speed.
3. **Passing.** The same robot drives straight past the cylinder on its right at gaps of
   0 to 39 mm: the widest gap at which a right-side sensor (diagonal, side, rear) reads it
   at all, and at which it reads it inside 4 cm, where ``robust``'s ``ClearanceGuard``
   takes the wheels.
4. **Together.** The share of head-on encounters in which that travel reaches the gap at
   first sight, per reflectance and link; and, with two obstacles a scene each drawn
   uniformly in the range, each met head-on by both robots over one link drawn at random,
   the share of runs with at least one such encounter.

Takes about a minute. Everything is seeded: the output is the same on every run.
"""

from __future__ import annotations

import math

import numpy as np

from puckboard.profile.links import LINKS, draw_timing
from puckboard.scenario.reality_gap import CONDITION_RANGES, REAL_LINKS
from puckboard.scenario.scene import CircleObstacle, Control, Noise, RobotSpec, Scene
from puckboard.sim.link_cycles import LinkCycleState
from puckboard.sim.world import World

SPEED = 2.0943951023931953  # rad/s, robust's wheel speed (V-REP's maxVel, 120 °/s)
WHEEL = 0.0205  # m, the physical e-puck's wheel radius
V = SPEED * WHEEL  # m/s
RHOS = (1.0, 0.5, 0.3, 0.2, 0.15, 0.1, 0.07, 0.05, 0.038)


def first_gap(rho: float, lateral: float, dt: float = 0.002) -> float:
    """The body-to-cylinder gap (m) when a front sensor first reads something."""
    ob = CircleObstacle(0.15, lateral, 0.03, ir_reflectance=rho, name="c")
    robot = RobotSpec("a", 0.0, 0.0, 0.0, profile="epuck")
    world = World(Scene("t", robots=(robot,), obstacles=(ob,), noise=Noise(), dt=dt), seed=0)
    radius = world.actual[0].body_radius
    for _ in range(int(0.2 / V / dt)):
        world.drive(0, SPEED, SPEED)
        world.step()
        x, y, _ = world.poses[0]
        gap = math.hypot(x - 0.15, y - lateral) - 0.03 - radius
        d = world.prox_distance[0]
        if min(d[7], d[0], d[6], d[1]) < 0.05:  # front_left, front_right, the diagonals
            return gap
        if gap <= 0.0:
            return 0.0
    return 0.0


def reaction(link: str, n: int = 4000, seed: int = 1, dt: float = 0.05) -> np.ndarray:
    """Seconds from the obstacle coming into range to the wheels acting on it."""
    rng = np.random.default_rng(seed)
    cycles = LINKS[link].cycles
    assert cycles is not None
    out = []
    for k in range(n):
        period, _ = draw_timing(LINKS[link], rng, dt)
        low, high = cycles.repeated
        repeated = low + float(rng.random()) * (high - low)
        control = Control(period=period, cycle_latency=cycles.latency, repeated=repeated)
        state = LinkCycleState(control, 1, seed=k, dt=dt)
        steps = round(period / dt)
        fresh = [state.fresh(0) for _ in range(80)]
        first = 30 + int(rng.integers(0, 20))  # a cycle well into the run
        seen_at = (first - 1 + float(rng.random())) * period
        cycle = first
        while not fresh[cycle]:
            cycle += 1
        state.send(0, cycle * steps, (0.0, 0.0))
        due = state.pending[0][-1][0]
        out.append(max(due * dt, cycle * period) - seen_at)
    return np.array(out)


def passing_reading(rho: float, gap: float, dt: float = 0.005) -> float:
    """The nearest distance (m) a right-side sensor reports while the robot drives
    straight past a cylinder whose surface is ``gap`` from its body."""
    robot = RobotSpec("a", 0.0, 0.0, 0.0, profile="epuck")
    world = World(Scene("t", robots=(robot,), noise=Noise(), dt=dt), seed=0)
    radius = world.actual[0].body_radius
    ob = CircleObstacle(0.10, -(radius + gap + 0.03), 0.03, ir_reflectance=rho, name="c")
    world = World(Scene("t", robots=(robot,), obstacles=(ob,), noise=Noise(), dt=dt), seed=0)
    nearest = 0.05
    for _ in range(int(0.2 / V / dt)):
        world.drive(0, SPEED, SPEED)
        world.step()
        d = world.prox_distance[0]
        nearest = min(nearest, d[1], d[2], d[3])  # diagonal_right, right, rear_right
    return nearest


def main() -> None:
    gaps = {rho: (first_gap(rho, 0.0), first_gap(rho, 0.01)) for rho in RHOS}
    print("reflectance  first seen at a gap of (mm): dead ahead / 1 cm off its axis")
    for rho in RHOS:
        print(f"{rho:11.3f}  {gaps[rho][0] * 1e3:5.1f} / {gaps[rho][1] * 1e3:5.1f}")
    travel = {link: reaction(link) * V * 1e3 for link in REAL_LINKS}
    print("\nlink               driven before the wheels act (mm): median, 90 %, largest")
    for link, mm in travel.items():
        print(f"{link:17s}  {np.median(mm):4.1f}  {np.quantile(mm, 0.9):4.1f}  {mm.max():4.1f}")
    print("\nreflectance  share of head-on encounters touched: " + "  ".join(REAL_LINKS))
    for rho in RHOS:
        gap = gaps[rho][0] * 1e3
        shares = "  ".join(f"{np.mean(travel[link] >= gap):.2f}" for link in REAL_LINKS)
        print(f"{rho:11.3f}  {shares}")
    print("\nreflectance  passing on the right: widest gap (mm) seen at all / read inside 4 cm")
    for rho in RHOS[:-1]:
        readings = [(g, passing_reading(rho, g / 1000)) for g in range(40)]
        seen = max((g for g, d in readings if d < 0.05), default=None)
        guard = max((g for g, d in readings if d < 0.04), default=None)
        print(f"{rho:11.3f}  {seen} / {guard}")
    r = CONDITION_RANGES["obstacle.ir_reflectance"]
    order = sorted(RHOS)
    touched = {
        link: lambda rho, mm=travel[link]: float(
            np.mean(mm >= np.interp(rho, order, [gaps[x][0] for x in order]) * 1e3)
        )
        for link in REAL_LINKS
    }
    rng = np.random.default_rng(7)
    runs, hit = 20000, 0
    for _ in range(runs):
        link = REAL_LINKS[int(rng.integers(len(REAL_LINKS)))]
        untouched = 1.0
        for rho in rng.uniform(r.low, r.high, size=2):
            untouched *= (1.0 - touched[link](rho)) ** 2  # both robots meet it
        hit += rng.random() > untouched
    print(
        f"\nruns with a head-on encounter touched (two obstacles, reflectance {r.low:g}-{r.high:g}, "
        f"a link at random): {hit / runs:.3f}"
    )


if __name__ == "__main__":
    main()
