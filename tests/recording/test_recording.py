import json
import math

import numpy as np
import pytest
from viz_standin import StandInEpisode

from puckboard.recording.recorder import FORMAT_VERSION, Recorder, load_recording


def _recorded(tmp_path, seconds=2.0):
    ep = StandInEpisode()
    recorder = Recorder.for_episode(ep, tmp_path / "run.npz").attach(ep)
    ep.run(seconds)
    return ep, recorder


def test_round_trip_has_a_series_per_robot_of_the_right_length(tmp_path):
    ep, recorder = _recorded(tmp_path)
    rec = load_recording(tmp_path / "run.npz")
    cycles = ep.loop.cycles
    assert cycles == 40
    assert len(rec) == cycles
    assert rec.robot_names == ("red", "blue")
    for name in rec.robot_names:
        s = rec.robot(name)
        assert s.pose.shape == (cycles, 3)
        assert s.wheels.shape == (cycles, 2)
        assert s.proximity.shape == (cycles, 8)
        assert s.ground.shape == (cycles, 3)
        assert s.layer_index.shape == (cycles,)
        assert s.layers[0] == "FrontObstacleLeftTurn"
    # time is the sensing time of each cycle: 0, dt, 2 dt, ...
    np.testing.assert_allclose(rec.time, np.arange(cycles) * 0.05, atol=1e-9)
    # the values are what the blackboard held
    red = rec.robot("red")
    assert red.proximity[0, 7] == pytest.approx(0.03)  # front_left as set on the fake
    assert red.layer_at(0) == "FrontObstacleLeftTurn"
    assert rec.robot("blue").layer_at(5) == "LineFollow"
    assert rec.robot("blue").ground[0, 1] == pytest.approx(0.1)
    wheels = ep.controllers["red"].last_command
    assert tuple(red.wheels[-1]) == pytest.approx((wheels.left, wheels.right))


def test_metadata_and_scene_survive_the_round_trip(tmp_path):
    ep, _ = _recorded(tmp_path, 0.5)
    rec = load_recording(tmp_path / "run.npz")
    assert rec.meta["version"] == FORMAT_VERSION
    assert rec.meta["scenario"] == "stand-in"
    assert rec.meta["controller"] == "improved"
    assert rec.meta["seed"] == 0
    assert rec.meta["colours"]["red"] == [200, 40, 40]
    scene = rec.scene
    assert scene.name == "stand-in"
    assert [r.name for r in scene.robots] == ["red", "blue"]
    # the scene file form keeps coordinates to the nanometre
    np.testing.assert_allclose(scene.track.points, ep.scene.track.points, atol=1e-9)
    assert scene.obstacles[0].radius == pytest.approx(0.03)
    assert scene.arena.xmax == pytest.approx(0.6)
    assert "stand-in" in rec.title and "seed 0" in rec.title


def test_recorded_scene_is_the_scene_file_form_and_loads_as_a_scene(tmp_path):
    from puckboard.scenario import scene_from_dict, scene_to_dict

    ep, _ = _recorded(tmp_path, 0.5)
    rec = load_recording(tmp_path / "run.npz")
    assert rec.meta["scene"] == json.loads(json.dumps(scene_to_dict(ep.scene)))
    # what a recording holds is a scene file: it loads through the same validation
    assert scene_to_dict(scene_from_dict(rec.meta["scene"])) == rec.meta["scene"]


def test_a_format_1_recording_gets_one_line_saying_to_record_again(tmp_path):
    ep, _ = _recorded(tmp_path, 0.5)
    rec = load_recording(tmp_path / "run.npz")
    rec.save(tmp_path / "old.npz")  # save stamps the current version: write the old one by hand
    with np.load(tmp_path / "old.npz") as data:
        arrays = {k: data[k] for k in data.files}
    meta = json.loads(str(arrays.pop("meta")))
    meta["version"] = 1
    np.savez(tmp_path / "old.npz", meta=np.array(json.dumps(meta)), **arrays)
    with pytest.raises(ValueError, match="format 1, which this puckboard no longer reads"):
        load_recording(tmp_path / "old.npz")


def test_recording_is_flushed_when_a_layer_raises(tmp_path):
    ep = StandInEpisode()
    Recorder.for_episode(ep, tmp_path / "crash.npz").attach(ep)
    calls = {"n": 0}

    def boom(_episode):
        calls["n"] += 1
        if calls["n"] == 7:
            raise RuntimeError("layer bug")

    ep.add_observer(boom)
    with pytest.raises(RuntimeError, match="layer bug"):
        ep.run(2.0)
    rec = load_recording(tmp_path / "crash.npz")
    assert len(rec) == 7


def test_recorder_grows_past_its_capacity_and_missing_keys_are_nan():
    from puckboard.blackboard import Blackboard
    from puckboard.records import WheelCommand

    board = Blackboard(clock=lambda: 0.0)
    recorder = Recorder(["a"], capacity=16)
    for k in range(50):
        board.put("a/command/wheels", WheelCommand(k, -k), stamp=k * 0.1)
        recorder.sample(board)
    rec = recorder.close()
    assert len(rec) == 50
    assert rec.wheels[49, 0, 0] == 49
    assert math.isnan(rec.pose[3, 0, 0])
    assert rec.layer[0, 0] == -1
    assert rec.robot("a").layer_at(0) is None


def test_bad_files_give_clear_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="no recording"):
        load_recording(tmp_path / "missing.npz")
    other = tmp_path / "other.npz"
    np.savez(other, x=np.zeros(3))
    with pytest.raises(ValueError, match="not a puckboard recording"):
        load_recording(other)
    with pytest.raises(ValueError, match=r"\.npz"):
        Recorder(["a"], path=tmp_path / "run.csv")


def test_meta_is_plain_json(tmp_path):
    _recorded(tmp_path, 0.2)
    with np.load(tmp_path / "run.npz", allow_pickle=False) as data:
        meta = json.loads(str(data["meta"]))
    assert meta["format"] == "puckboard-recording"
    assert meta["robots"] == ["red", "blue"]


def test_the_file_holds_the_arrays_in_their_table_order_with_their_types(tmp_path):
    """One table names the arrays: the file's members, their types and shapes follow it."""
    import zipfile

    from puckboard.recording.recorder import _ARRAYS

    _recorded(tmp_path, 0.5)
    members = [n.removesuffix(".npy") for n in zipfile.ZipFile(tmp_path / "run.npz").namelist()]
    assert members[: len(_ARRAYS) + 1] == [*_ARRAYS, "meta"]
    rec = load_recording(tmp_path / "run.npz")
    for name, arr in rec.arrays().items():
        dtype, tail = _ARRAYS[name]
        assert arr.dtype == dtype, name
        assert arr.shape == ((len(rec),) if tail is None else (len(rec), 2, *tail)), name


def test_robot_layers_are_the_controllers_own_layers(tmp_path):
    ep, recorder = _recorded(tmp_path, 0.2)
    for name, controller in ep.controllers.items():
        assert recorder.robot_layers[name] == tuple(c.name for c in controller.every_layer)


def test_metadata_that_is_no_json_is_refused_in_one_line(tmp_path):
    from dataclasses import dataclass

    @dataclass
    class Opaque:
        x: int = 1

    recorder = Recorder(["a"], meta={"thing": Opaque()})
    with pytest.raises(TypeError, match="cannot store Opaque in a recording's metadata"):
        recorder.close().save(tmp_path / "run.npz")
