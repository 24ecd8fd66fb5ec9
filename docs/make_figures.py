"""Draw the documentation's figures into docs/img/ from puckboard's own code.

Every number in a plot comes from running the real layers (or the real simulator), so a
picture cannot drift away from what the code does. Run it after changing a layer::

    python docs/make_figures.py            # all figures
    python docs/make_figures.py sensors    # only the ones whose name contains "sensors"

Needs the ``viz`` extra (matplotlib).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, FancyArrowPatch, FancyBboxPatch, Rectangle

from puckboard.backends import FakeAdapter
from puckboard.behaviours import (
    Controller,
    Cruise,
    FrontBraitenbergAvoid,
    FrontObstacleLeftTurn,
    HoldFor,
    Layer,
    LineFollow,
    SideWallKeep,
    improved,
)
from puckboard.blackboard import Blackboard
from puckboard.control import ControlLoop
from puckboard.profile import EPUCK2
from puckboard.records import GROUND_NAMES, PROX_NAMES, VREP_ORDER, Ground, Proximity

IMG = Path(__file__).resolve().parent / "img"
DPI = 110
LEFT_C, RIGHT_C = "#1f77b4", "#d62728"
STOCK_C, IMPROVED_C = "#d62728", "#2ca02c"


# -- helpers ------------------------------------------------------------------------------
_PROBES: dict[int, Controller] = {}


def command_of(layer: Layer, **records: object) -> tuple[float, float, bool]:
    """(left, right, applies) of ``layer`` for the given blackboard records.

    The layer is ticked inside a one-layer Controller, exactly as in a run.
    """
    ctrl = _PROBES.get(id(layer))
    if ctrl is None:
        ctrl = _PROBES[id(layer)] = Controller([layer])
    board = Blackboard(clock=lambda: 0.0)
    ns = board.namespace("robot")
    for key, value in records.items():
        ns.put(key, value)
    cmd = ctrl.tick(ns)
    return cmd.left, cmd.right, ctrl.active_layer == layer.name


def proximity(**distances: float) -> Proximity:
    d = np.full(8, EPUCK2.prox_range)
    for name, value in distances.items():
        d[PROX_NAMES.index(name)] = value
    return Proximity(d, np.zeros(8), EPUCK2.prox_range)


def ground(*dark: str) -> Ground:
    v = np.array([0.1 if n in dark else 0.9 for n in GROUND_NAMES])
    return Ground(v, v * 1023)


def draw_robot(  # type: ignore[no-untyped-def]
    ax, x: float, y: float, theta: float, colour: str = "#cccccc", scale: float = 1.0,
    heading: bool = True,
):  # fmt: skip
    """An e-puck seen from above: body, two wheels and a heading arrow."""
    r = EPUCK2.body_radius * scale
    ax.add_patch(Circle((x, y), r, fc=colour, ec="black", lw=1.2, zorder=3))
    c, s = math.cos(theta), math.sin(theta)
    half_axle = EPUCK2.axle_length / 2 * scale
    wr = EPUCK2.wheel_radius * scale
    width = 0.004 * scale
    for side in (1, -1):
        wx, wy = x - s * side * half_axle, y + c * side * half_axle
        corner = (wx - c * wr + s * width / 2, wy - s * wr - c * width / 2)
        ax.add_patch(
            Rectangle(corner, 2 * wr, width, angle=math.degrees(theta), fc="#444444", zorder=4)
        )
    if heading:
        ax.annotate(
            "", xy=(x + c * r * 0.8, y + s * r * 0.8), xytext=(x - c * r * 0.2, y - s * r * 0.2),
            arrowprops={"arrowstyle": "-|>", "color": "black", "lw": 1.5, "mutation_scale": 15},
            zorder=5,
        )  # fmt: skip


def save(fig, name: str) -> None:  # type: ignore[no-untyped-def]
    IMG.mkdir(parents=True, exist_ok=True)
    path = IMG / f"{name}.png"
    fig.savefig(path, dpi=DPI, bbox_inches="tight", facecolor="white")
    plt.close(fig)
    print(f"wrote {path.relative_to(IMG.parent.parent)}")


# -- figures ------------------------------------------------------------------------------
def fig_sensors() -> None:
    """Sensor layout: names, real ps numbers and V-REP numbers, ground sensors."""
    fig, ax = plt.subplots(figsize=(6.4, 5.6))
    draw_robot(ax, 0, 0, math.pi / 2, colour="#eeeeee", heading=False)
    ax.annotate(
        "forward", xy=(-0.066, 0.045), xytext=(-0.066, 0.012), ha="center", va="top", fontsize=9,
        arrowprops={"arrowstyle": "-|>", "color": "black", "lw": 1.5},
    )  # fmt: skip
    vrep_of = {ps: k + 1 for k, ps in enumerate(VREP_ORDER)}
    for i, pose in enumerate(EPUCK2.prox_poses):
        # robot frame x forward, y left; drawn with forward = up
        px, py = -pose.y, pose.x
        hx, hy = -math.sin(pose.heading), math.cos(pose.heading)
        ax.plot(px, py, "o", color="#ff7f0e", ms=8, mec="black", zorder=8)
        ax.annotate(
            "", xy=(px + hx * 0.012, py + hy * 0.012), xytext=(px, py),
            arrowprops={"arrowstyle": "->", "color": "#ff7f0e", "lw": 1.5}, zorder=6,
        )  # fmt: skip
        lx, ly = px + hx * 0.024, py + hy * 0.024
        ax.text(
            lx, ly, f"ps{i}  {PROX_NAMES[i]}\nV-REP sensor {vrep_of[i]}",
            ha="center", va="center", fontsize=8.5,
            bbox={"boxstyle": "round,pad=0.25", "fc": "white", "ec": "#ff7f0e"},
        )  # fmt: skip
    for i, pose in enumerate(EPUCK2.ground_poses):
        gx, gy = -pose.y, pose.x
        gy -= 0.012  # drawn a little behind the IR sensors so both stay visible
        ax.add_patch(Rectangle((gx - 0.002, gy - 0.002), 0.004, 0.004, fc="black", zorder=6))
        ax.text(gx, gy - 0.004, f"gs{i}\n{GROUND_NAMES[i]}", ha="center", va="top", fontsize=7)
    ax.text(0, -0.012, "ground sensors (underneath,\n30 mm ahead of the axle)", ha="center",
            va="top", fontsize=7, style="italic")  # fmt: skip
    ax.set_xlim(-0.075, 0.075)
    ax.set_ylim(-0.06, 0.075)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(
        "e-puck seen from above (driving up the page)\n"
        "ps0..ps7 clockwise from front right; V-REP numbers 1..8 from the left side",
        fontsize=10,
    )
    save(fig, "sensors")


def fig_line_follow() -> None:
    """Wheel commands of LineFollow for each pattern of dark ground sensors."""
    patterns = [
        ("left",),
        ("left", "centre"),
        ("centre",),
        ("centre", "right"),
        ("right",),
        ("left", "centre", "right"),
        ("left", "right"),
    ]
    labels = ["all" if len(p) == 3 else "+".join(n[0].upper() for n in p) for p in patterns]
    variants = [
        ("stock: LineFollow(inner_factor=0.25)", LineFollow(inner_factor=0.25)),
        ("improved: LineFollow(inner_factor=0.20, recovery=True)",
         LineFollow(inner_factor=0.20, recovery=True)),
    ]  # fmt: skip
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), sharey=True)
    x = np.arange(len(patterns))
    for ax, (title, layer) in zip(axes, variants):
        cmds = [command_of(layer, ground=ground(*p))[:2] for p in patterns]
        left = [c[0] for c in cmds]
        right = [c[1] for c in cmds]
        ax.bar(x - 0.2, left, 0.4, color=LEFT_C, label="left wheel")
        ax.bar(x + 0.2, right, 0.4, color=RIGHT_C, label="right wheel")
        ax.axhline(0, color="black", lw=0.8)
        ax.set_xticks(x, labels, fontsize=10)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("ground sensors that see the line (L left, C centre, R right)")
        ax.grid(axis="y", alpha=0.3)
    axes[0].set_ylabel("wheel speed (rad/s)")
    axes[0].legend(loc="lower left", fontsize=8)
    fig.suptitle(
        "LineFollow: slow the wheel on the side that sees the line; the improved "
        "version reverses it at sharp corners",
        fontsize=10,
    )
    save(fig, "line-follow")


def fig_front_obstacle() -> None:
    """Turn rate chosen by the two avoidance layers when one front sensor sees something."""
    sensors = ["diagonal_left", "front_left", "front_right", "diagonal_right"]
    layers = [
        ("FrontBraitenbergAvoid (stock)", FrontBraitenbergAvoid(), STOCK_C),
        ("FrontObstacleLeftTurn (improved)", FrontObstacleLeftTurn(), IMPROVED_C),
    ]
    fig, ax = plt.subplots(figsize=(7.5, 3.8))
    x = np.arange(len(sensors))
    for k, (label, layer, colour) in enumerate(layers):
        rates = []
        for name in sensors:
            left, right, _ = command_of(layer, proximity=proximity(**{name: 0.02}))
            rates.append(EPUCK2.body_velocity(left, right)[1])
        ax.bar(x + (k - 0.5) * 0.38, rates, 0.38, color=colour, label=label)
    ax.axhline(0, color="black", lw=0.8)
    ax.set_xticks(x, [f"{s}\n(obstacle 2 cm)" for s in sensors], fontsize=9)
    ax.set_ylabel("turn rate (rad/s)\n+ = turns left,  − = turns right")
    ax.legend(fontsize=8, loc="upper center", ncol=2, bbox_to_anchor=(0.5, -0.22))
    ax.grid(axis="y", alpha=0.3)
    ax.set_title(
        "Which way does the robot turn when one front sensor sees an obstacle?\n"
        "stock turns away from it (either way); improved always turns left first",
        fontsize=10,
    )
    save(fig, "front-obstacle")


def fig_side_wall_keep() -> None:
    """Wheel speeds of SideWallKeep(('right',)) against the right side distance."""
    fig, ax = plt.subplots(figsize=(7.5, 3.6))
    distances = np.linspace(0.0, EPUCK2.prox_range, 201)
    layer = SideWallKeep(("right",))
    cmds = [command_of(layer, proximity=proximity(right=float(d))) for d in distances]
    left = np.array([c[0] if c[2] else np.nan for c in cmds])
    right = np.array([c[1] if c[2] else np.nan for c in cmds])
    ax.plot(distances * 100, left, color=LEFT_C, lw=2, label="left wheel")
    ax.plot(distances * 100, right, color=RIGHT_C, lw=2, label="right wheel (on the wall's side)")
    near = layer.near_fraction * EPUCK2.prox_range * 100
    ax.axvspan(0, near, color="grey", alpha=0.15)
    ax.text(near / 2, 0.3, "closer than\nnear_fraction × range:\nlayer does not apply",
            fontsize=8, ha="center", va="bottom")  # fmt: skip
    ax.text(EPUCK2.prox_range * 100 - 0.05, 0.3, "nothing seen:\nlayer does\nnot apply",
            fontsize=8, ha="right", va="bottom")  # fmt: skip
    ax.set_xlabel("distance seen by the right side sensor (cm); 5 cm = nothing seen")
    ax.set_ylabel("wheel speed (rad/s)")
    ax.set_ylim(0, None)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right", bbox_to_anchor=(0.99, 0.3))
    ax.set_title(
        "SideWallKeep (right side): the closer the wall, the slower the right wheel,\n"
        "so the robot curves towards the obstacle and hugs its contour",
        fontsize=10,
    )
    save(fig, "side-wall-keep")


def _box(ax, x: float, y: float, w: float, h: float, text: str, colour: str) -> None:  # type: ignore[no-untyped-def]
    ax.add_patch(
        FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.02", fc=colour, ec="black", lw=1)
    )
    ax.text(x + w / 2, y + h / 2, text, ha="center", va="center", fontsize=9)


def _arrow(ax, start, end, colour: str = "black") -> None:  # type: ignore[no-untyped-def]
    ax.add_patch(
        FancyArrowPatch(start, end, arrowstyle="-|>", mutation_scale=12, color=colour, lw=1.2)
    )


def fig_subsumption() -> None:
    """The improved controller as a priority stack with Cruise at the bottom."""
    ctrl = improved()
    names = [layer.name for layer in ctrl.layers]
    conditions = {
        "FrontObstacleLeftTurn": "a front sensor sees\nsomething < 5 cm",
        "LineFollow": "a ground sensor\nsees the line",
        "SideWallKeep": "the right side sensor sees\nsomething 1.25–5 cm away",
        "Cruise": "always",
    }
    fig, ax = plt.subplots(figsize=(8.2, 4.4))
    n = len(names)
    for i, name in enumerate(names):
        y = (n - 1 - i) * 1.0
        _box(ax, 0.0, y + 0.1, 2.6, 0.7, f"{i + 1}. {name}", "#dfe8f5" if i else "#f9d7d2")
        ax.text(2.8, y + 0.45, "applies when\n" + conditions.get(name, "?"), fontsize=8,
                va="center")  # fmt: skip
        _arrow(ax, (5.3, y + 0.45), (6.3, 1.95 if i < n - 1 else 1.6))
    _box(ax, 6.3, 1.3, 1.6, 1.0, "arbiter\n(Selector)\nfirst that\napplies wins", "#fff3c4")
    _arrow(ax, (7.9, 1.8), (8.6, 1.8))
    ax.text(8.65, 1.8, "wheels\n(left, right)\nrad/s", va="center", fontsize=9)
    ax.text(0.0, n + 0.05, "priority: high", fontsize=9, style="italic")
    ax.text(0.0, -0.3, "priority: low", fontsize=9, style="italic")
    ax.set_xlim(-0.1, 9.8)
    ax.set_ylim(-0.5, n + 0.4)
    ax.axis("off")
    ax.set_title(
        "Subsumption: each layer is a whole behaviour; a higher layer that applies\n"
        "suppresses everything below it (the improved controller)",
        fontsize=10,
    )
    save(fig, "subsumption")


def fig_hold_for() -> None:
    """A short trigger, and how HoldFor stretches it into a whole manoeuvre."""

    class Backoff(Layer):
        """Reverse while the rear-independent front sensors see something."""

        reads = ("proximity",)

        def applies(self, frame):  # type: ignore[no-untyped-def]
            prox = frame.proximity
            return prox is not None and prox.front_left < prox.range

        def command(self, frame):  # type: ignore[no-untyped-def]
            from puckboard.records import WheelCommand

            return WheelCommand(-2.0, -2.0)

    fig, axes = plt.subplots(2, 1, figsize=(7.5, 3.8), sharex=True)
    for ax, hold in zip(axes, (0.0, 0.5)):
        robot = FakeAdapter()
        layer = Backoff()
        top = HoldFor(layer, hold) if hold else layer
        ctrl = Controller([top, Cruise()], requires=("proximity",))
        trigger: list[float] = []
        active: list[float] = []
        times: list[float] = []

        def script(loop: ControlLoop, robot: FakeAdapter = robot) -> None:
            t = loop.time
            if 1.0 <= t < 1.2:
                robot.set_proximity(front_left=0.02)
            else:
                robot.set_proximity()

        def record(
            loop: ControlLoop,
            ctrl: Controller = ctrl,
            robot: FakeAdapter = robot,
            trigger: list[float] = trigger,
            active: list[float] = active,
            times: list[float] = times,
        ) -> None:
            times.append(loop.time - loop.period)  # the time this cycle sensed at
            trigger.append(float(robot.ns.get("proximity").value.front_left < 0.05))
            active.append(float(ctrl.active_layer == "Backoff"))

        loop = ControlLoop([(robot, ctrl)])
        loop.add_before_tick(script)
        loop.add_observer(record)
        loop.run(3.0)
        ax.fill_between(times, 0, trigger, step="post", color="#ff7f0e", alpha=0.5,
                        label="trigger: front_left sees an obstacle")  # fmt: skip
        ax.step(times, active, where="post", color="black", lw=1.8,
                label="Backoff has the wheels")  # fmt: skip
        ax.set_yticks([0, 1], ["no", "yes"])
        ax.set_ylim(-0.15, 1.4)
        title = f"HoldFor(Backoff(), {hold} s)" if hold else "Backoff() alone"
        ax.set_title(title, fontsize=9, loc="left")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper right", ncol=2)
    axes[1].set_xlabel("simulation time (s)")
    fig.suptitle("HoldFor keeps a layer in control for a while after its trigger ends", fontsize=10)
    save(fig, "hold-for")


def fig_blackboard() -> None:
    """Who writes and who reads which keys of one robot's blackboard."""
    fig, ax = plt.subplots(figsize=(9, 4.4))
    board_x, board_w = 3.3, 3.0
    keys = [
        ("proximity", "adapter"),
        ("ground", "adapter"),
        ("encoders", "adapter"),
        ("percept/line_position", "source"),
        ("estimate/distance_m", "source"),
        ("command/wheels", "controller"),
        ("command/layer", "controller"),
    ]
    ax.add_patch(
        FancyBboxPatch((board_x, 0.2), board_w, 4.8, boxstyle="round,pad=0.05", fc="#fff8dc",
                       ec="black", lw=1.2)
    )  # fmt: skip
    ax.text(board_x + board_w / 2, 4.55, "blackboard of robot left/", ha="center",
            fontsize=10, weight="bold")  # fmt: skip
    colours = {"adapter": "#dfe8f5", "source": "#e2f0d9", "controller": "#f9d7d2"}
    key_y = {}
    for i, (key, writer) in enumerate(keys):
        y = 3.95 - i * 0.55
        key_y[key] = y
        _box(ax, board_x + 0.25, y - 0.2, board_w - 0.5, 0.4, key, colours[writer])
    _box(
        ax,
        0.0,
        2.9,
        2.3,
        0.9,
        "robot adapter\n(simulator, CoppeliaSim,\nreal e-puck)",
        colours["adapter"],
    )
    _box(
        ax,
        0.0,
        1.1,
        2.3,
        0.9,
        "knowledge sources\n(interpretation,\nintegration)",
        colours["source"],
    )
    _box(
        ax,
        7.4,
        1.6,
        2.3,
        1.2,
        "controller\n(layers + arbiter)\nreads a snapshot",
        colours["controller"],
    )
    for key in ("proximity", "ground", "encoders"):
        _arrow(ax, (2.3, 3.35), (board_x + 0.25, key_y[key]), "#1f4e9c")
    _arrow(ax, (board_x + 0.25, key_y["ground"]), (2.3, 1.75), "#2e7d32")
    _arrow(ax, (board_x + 0.25, key_y["encoders"]), (2.3, 1.55), "#2e7d32")
    for key in ("percept/line_position", "estimate/distance_m"):
        _arrow(ax, (2.3, 1.35), (board_x + 0.25, key_y[key]), "#2e7d32")
    for key in ("proximity", "ground", "percept/line_position"):
        _arrow(ax, (board_x + board_w - 0.25, key_y[key]), (7.4, 2.5), "#555555")
    for key in ("command/wheels", "command/layer"):
        _arrow(ax, (7.4, 1.9), (board_x + board_w - 0.25, key_y[key]), "#b23a2a")
    ax.text(7.45, 0.55, "wheel command → adapter\n(once per control cycle)", fontsize=8,
            style="italic")  # fmt: skip
    ax.set_xlim(-0.1, 9.8)
    ax.set_ylim(0.0, 5.2)
    ax.axis("off")
    ax.set_title(
        "Modules meet only on the blackboard: each writes its keys and reads the keys it "
        "is interested in", fontsize=10,
    )  # fmt: skip
    save(fig, "blackboard")


class TurnLeftFirst(Layer):
    """The first layer the tutorial's reader writes (step 4), repeated here to draw it."""

    reads = ("proximity",)

    def __init__(self, speed: float = 2.0) -> None:
        super().__init__()
        self.speed = speed

    def applies(self, frame):  # type: ignore[no-untyped-def]
        prox = frame.proximity
        if prox is None:
            return False
        front = [prox.diagonal_left, prox.front_left, prox.front_right, prox.diagonal_right]
        return min(front) < prox.range

    def command(self, frame):  # type: ignore[no-untyped-def]
        from puckboard.records import WheelCommand

        return WheelCommand(-self.speed / 2, self.speed)


class FindLineOnTheRight(Layer):
    """The second layer the tutorial's reader writes (step 5), repeated here to draw it."""

    reads = ("ground",)

    def __init__(self, speed: float = 2.0, ratio: float = 0.8) -> None:
        super().__init__()
        self.speed = speed
        self.ratio = ratio

    def applies(self, frame):  # type: ignore[no-untyped-def]
        ground = frame.ground
        return ground is not None and not ground.dark().any()

    def command(self, frame):  # type: ignore[no-untyped-def]
        from puckboard.records import WheelCommand

        return WheelCommand(self.speed, self.ratio * self.speed)


def tutorial_controller() -> Controller:
    """The tutorial's controller (step 5)."""
    return Controller(
        [
            TurnLeftFirst(),
            LineFollow(inner_factor=0.2, recovery=True),
            SideWallKeep(("right",)),
            FindLineOnTheRight(),
            Cruise(),
        ],
        name="tutorial",
        requires=("proximity",),
    )


def fig_two_robot_pass() -> None:
    """Trajectories of the two-robot pass: stock, improved, and the tutorial's controller."""
    from puckboard.control.episode import Episode
    from puckboard.viz.scene_art import draw_scene, scene_bounds

    runs = [
        ("stock", "stock"),
        ("improved", "improved"),
        ("the tutorial's controller", tutorial_controller),
    ]
    done = []
    for label, controller in runs:
        episode = Episode("two-robot-pass", controller=controller, seed=0)
        paths: list[np.ndarray] = []

        def keep(ep: Episode, paths: list[np.ndarray] = paths) -> None:
            paths.append(ep.world.poses[:, :2].copy())

        episode.add_observer(keep)
        done.append((label, episode, episode.run(), np.array(paths)))  # paths: T × N × 2
    everything = np.concatenate([track.reshape(-1, 2) for *_, track in done])
    xmin, xmax, ymin, ymax = scene_bounds(done[0][1].scene, everything)
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.1))
    for ax, (label, episode, result, track) in zip(axes, done):
        draw_scene(ax, episode.scene, labels=False)
        for k, spec in enumerate(episode.scene.robots):
            colour = np.array(spec.colour) / 255
            ax.plot(track[:, k, 0], track[:, k, 1], color=colour, lw=2, label=spec.name)
            ax.plot(*track[0, k], "o", color=colour, ms=7, mec="black")
            ax.plot(*track[-1, k], "s", color=colour, ms=7, mec="black")
        ax.set_xlim(xmin, xmax)
        ax.set_ylim(ymin, ymax)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        verdict = "passed" if result.success else f"failed: {result.failure}"
        ax.set_title(f"{label}\n{verdict} after {result.sim_time_s:.0f} s", fontsize=10)
    axes[0].legend(fontsize=8, loc="upper left")
    fig.suptitle("The two-robot pass, seed 0 (● start, ■ end of the run)", fontsize=11)
    fig.subplots_adjust(top=0.8, bottom=0.02, wspace=0.04)
    save(fig, "two-robot-pass")


def fig_task_tree() -> None:
    """The task tree of examples/task_control.py, drawn by puckboard's own tree renderer
    (needs Graphviz's ``dot``)."""
    import importlib.util

    from puckboard.viz.tree import render_tree

    path = IMG.parent.parent / "examples" / "task_control.py"
    spec = importlib.util.spec_from_file_location("task_control_example", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    png = render_tree(module.mission(), "png")
    assert isinstance(png, bytes)
    (IMG / "task-tree.png").write_bytes(png)
    print(f"wrote {(IMG / 'task-tree.png').relative_to(IMG.parent.parent)}")


FIGURES: dict[str, Callable[[], None]] = {
    "task-tree": fig_task_tree,
    "two-robot-pass": fig_two_robot_pass,
    "sensors": fig_sensors,
    "line-follow": fig_line_follow,
    "front-obstacle": fig_front_obstacle,
    "side-wall-keep": fig_side_wall_keep,
    "subsumption": fig_subsumption,
    "blackboard": fig_blackboard,
    "hold-for": fig_hold_for,
}


def main(argv: list[str]) -> int:
    wanted = [name for name in FIGURES if not argv or any(a in name for a in argv)]
    for name in wanted:
        FIGURES[name]()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
