"""generated-pass: every seed draws a valid two-robot pass on its own track; a seed's
scene printed by 'scenes show --seed' runs to the same result as the generated scene."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from puckboard.cli import main
from puckboard.control.episode import Episode, run_episode
from puckboard.errors import SceneError
from puckboard.profile import get_profile
from puckboard.scenario.conversion import for_seed, scene_from_dict, scene_to_dict
from puckboard.scenario.generated import SIZE_X, SIZE_Y
from puckboard.scenario.judge import Judge
from puckboard.scenario.placement import TrackFrame
from puckboard.scenario.scene import CircleObstacle
from puckboard.scenario.scenefile import load_scene, parse_scene_text
from puckboard.sweep.options import RunOptions

GENERATED = load_scene("generated-pass")


def _distance_to_line(scene, points: np.ndarray) -> np.ndarray:
    seg = scene.track.segments()
    a, e = seg[:, 0], seg[:, 1] - seg[:, 0]
    d = points[:, None, :] - a[None]
    t = np.clip((d * e).sum(-1) / (e * e).sum(-1), 0.0, 1.0)
    return np.linalg.norm(d - t[..., None] * e, axis=-1).min(axis=1)


def _extent(ob) -> float:
    """How far an obstacle reaches from its centre."""
    if isinstance(ob, CircleObstacle):
        return ob.radius
    v = np.asarray(ob.vertices)
    return float(np.linalg.norm(v - v.mean(axis=0), axis=1).max())


def _centre(ob) -> np.ndarray:
    if isinstance(ob, CircleObstacle):
        return np.array([ob.x, ob.y])
    return np.asarray(ob.vertices).mean(axis=0)


@pytest.mark.parametrize("seeds", [range(0, 100), range(100_000, 100_100)])
def test_every_seed_draws_a_valid_pass(seeds):
    kinds = set()
    for seed in seeds:
        scene = for_seed(GENERATED, seed)
        assert scene.generate is None and scene.goal.kind == "pass"
        pts = scene.track.points
        span = pts.max(axis=0) - pts.min(axis=0)
        assert SIZE_X[0] - 1e-9 <= span[0] <= SIZE_X[1] + 1e-9
        assert SIZE_Y[0] - 1e-9 <= span[1] <= SIZE_Y[1] + 1e-9
        body = max(get_profile(r.profile).body_radius for r in scene.robots)
        starts = np.array([[r.x, r.y] for r in scene.robots])
        # the robots start on the line, facing each other along it, far enough apart
        assert (_distance_to_line(scene, starts) < 1e-6).all(), seed
        assert np.linalg.norm(starts[0] - starts[1]) >= 0.3, seed
        frame = TrackFrame(scene.track)
        assert frame.length > 2.0 and scene.duration > 0
        # both obstacles stand on the line, clear of the robots and of each other
        judge = Judge(scene)
        assert len(judge.track_obstacles) == 2, seed
        for ob in scene.obstacles:
            c = _centre(ob)
            assert _distance_to_line(scene, c[None])[0] < 1e-6, seed
            for s in starts:
                assert np.linalg.norm(c - s) - _extent(ob) - body >= 0.1, seed
            kinds.add(type(ob).__name__)
        a, b = (_centre(ob) for ob in scene.obstacles)
        assert (
            np.linalg.norm(a - b) - _extent(scene.obstacles[0]) - _extent(scene.obstacles[1])
            > 2 * body
        )
        kinds.add("bend" if "bend" in scene.description else "straight")
    assert kinds == {"CircleObstacle", "PolygonObstacle", "bend", "straight"}


def test_seeds_draw_different_tracks_and_one_seed_always_the_same():
    assert scene_to_dict(for_seed(GENERATED, 7)) == scene_to_dict(for_seed(GENERATED, 7))
    lengths = {round(TrackFrame(for_seed(GENERATED, s).track).length, 6) for s in range(20)}
    assert len(lengths) == 20
    episode = Episode("generated-pass", seed=8, variation="plausible")
    assert scene_to_dict(episode.scene)["track"] == scene_to_dict(for_seed(GENERATED, 8))["track"]
    assert episode.scene.robots[0].actual is not None
    episode.connection.close()


def test_the_printed_scene_runs_to_the_same_result(capsys, tmp_path):
    assert main(["scenes", "show", "generated-pass", "--seed", "7"]) == 0
    text = capsys.readouterr().out
    path = tmp_path / "seed7.toml"
    path.write_text(text, encoding="utf-8")
    printed = parse_scene_text(text, source=str(path))
    assert scene_to_dict(printed) == scene_to_dict(for_seed(GENERATED, 7))
    results = [
        run_episode(s, seed=7, duration=3.0, stop_early=False).to_dict()
        for s in (str(path), "generated-pass")
    ]
    for r in results:
        r.pop("wall_s"), r.pop("realtime_factor")
    assert results[0] == results[1]
    assert results[0]["scenario"] == "generated-pass"


def test_scenes_lists_it_and_seed_is_for_generated_scenes_only(capsys):
    assert main(["scenes"]) == 0
    assert "generated-pass" in capsys.readouterr().out
    assert main(["scenes", "show", "two-robot-pass", "--seed", "3"]) == 2
    err = capsys.readouterr().err
    assert "is not generated" in err and err.count("\n") == 1


def test_a_generated_scene_file_draws_its_own_obstacles():
    data = json.loads(GENERATED.generate or "{}")
    data["obstacles"] = [{"x": 0.0, "y": 0.0, "radius": 0.02}]
    with pytest.raises(SceneError, match="draws its obstacles"):
        scene_from_dict(data, source="mine.toml")


def test_it_is_judged_like_the_pass_scenes():
    result = run_episode("generated-pass", controller="robust", seed=3, duration=2.0)
    metrics = result.to_dict()["robots"]
    assert [m["name"] for m in metrics] == ["left", "right"]
    assert all("obstacles_passed" in m and "passed_other" in m for m in metrics)
    assert all(m["progress_laps"] > 0.0 and math.isfinite(m["progress_laps"]) for m in metrics)


def test_a_sweep_over_seeds_is_a_sweep_over_tracks():
    from puckboard.sweep import InlineExecutor, SweepPlan, run_sweep

    plan = SweepPlan.from_specs(
        "generated-pass", controllers=["robust"], seeds="5:7", fixed={"duration": 1.0}
    )
    result = run_sweep(plan, GENERATED, RunOptions(executor=InlineExecutor()))
    by_seed = {o.seed: o for o in result.outcomes}
    assert sorted(by_seed) == [5, 6]

    def mean_laps(scene, seed: int) -> float:
        robots = run_episode(scene, controller="robust", seed=seed, duration=1.0).to_dict()[
            "robots"
        ]
        return sum(m["progress_laps"] for m in robots) / len(robots)  # as a row gives it

    for seed, outcome in by_seed.items():
        # each seed ran on its own track, not on the file's (seed 0's)
        assert outcome.progress_laps == pytest.approx(
            mean_laps(for_seed(GENERATED, seed), seed), abs=1e-5
        )
        assert outcome.progress_laps != pytest.approx(
            mean_laps(for_seed(GENERATED, 0), seed), abs=1e-5
        )
