"""Recordings keep what each arbiter decided every tick: node statuses and what was read."""

from __future__ import annotations

import json

import numpy as np
import pytest
from viz_standin import StandInEpisode

from puckboard.behaviours import Controller, Cruise, Layer
from puckboard.blackboard import Blackboard
from puckboard.recording.recorder import FORMAT_VERSION, Recorder, load_recording
from puckboard.records import WheelCommand


def recorded(tmp_path, seconds=2.0, **options):
    ep = StandInEpisode()
    recorder = Recorder.for_episode(ep, tmp_path / "run.npz", **options).attach(ep)
    ep.run(seconds)
    return ep, recorder


def test_the_tree_statuses_tell_the_same_story_as_the_layer_in_control(tmp_path):
    recorded(tmp_path)
    rec = load_recording(tmp_path / "run.npz")
    assert rec.meta["version"] == 3  # the format that first held the decisions
    d = rec.decisions
    assert d is not None and d.status.shape == (len(rec), 2, 5)
    for name in rec.robot_names:
        nodes = [n["name"] for n in d.trees[name]]
        layers = nodes[1:]
        assert nodes[0] == "improved" and layers == list(rec.robot(name).layers)
        for tick in range(len(rec)):
            status = rec.tree_at(name, tick)
            winner = rec.robot(name).layer_at(tick)
            k = layers.index(winner)  # the selector asked down to the winner, and no further
            assert [status[n] for n in layers] == (
                ["FAILURE"] * k + ["RUNNING"] + ["not ticked"] * (len(layers) - k - 1)
            ), (name, tick)
            assert status["improved"] == "RUNNING"
    # the stand-in's red robot sees an obstacle in front, the blue one a line
    assert rec.tree_at("red", 0)["FrontObstacleLeftTurn"] == "RUNNING"
    assert rec.tree_at("blue", 5)["LineFollow"] == "RUNNING"


def test_the_values_the_layers_read_are_kept_with_their_ages_and_stored_once(tmp_path):
    recorded(tmp_path, 1.0)
    rec = load_recording(tmp_path / "run.npz")
    d = rec.decisions
    assert d.keys == ("ground", "proximity")
    assert d.robot_reads == {"red": ["ground", "proximity"], "blue": ["ground", "proximity"]}
    # what the layers read is what the blackboard held, as the recording's own arrays say
    np.testing.assert_array_equal(d.values["proximity"], rec.proximity)
    np.testing.assert_array_equal(d.values["ground"], rec.ground)
    assert d.values["proximity"][0, 0, 7] == pytest.approx(0.03)
    # sensed this very cycle: age zero, fresh
    assert np.all(d.age == 0) and np.all(d.fresh == 1)
    with np.load(tmp_path / "run.npz") as data:
        files = set(data.files)
        meta = json.loads(str(data["meta"]))
    assert {"tree", "read_age", "read_status"} <= files
    assert not any(f.startswith("read_") and f[5:].isdigit() for f in files)  # no copies
    assert [r["array"] for r in meta["reads"]] == ["ground", "proximity"]


def test_without_decisions_the_other_arrays_are_bit_for_bit_the_same(tmp_path):
    recorded(tmp_path / "a", 1.0)
    recorded(tmp_path / "b", 1.0, decisions=False)
    a, b = load_recording(tmp_path / "a" / "run.npz"), load_recording(tmp_path / "b" / "run.npz")
    assert b.decisions is None and a.decisions is not None
    for name in ("time", "pose", "wheels", "layer", "proximity", "ground"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


def test_a_format_2_recording_still_loads_without_decisions(tmp_path):
    recorded(tmp_path, 0.5)
    with np.load(tmp_path / "run.npz") as data:
        arrays = {k: data[k] for k in data.files if k in
                  ("time", "pose", "wheels", "layer", "proximity", "ground")}  # fmt: skip
        meta = json.loads(str(data["meta"]))
    for key in ("trees", "tree_status", "reads", "robot_reads"):
        meta.pop(key)
    meta["version"] = 2
    np.savez(tmp_path / "old.npz", meta=np.array(json.dumps(meta)), **arrays)
    old = load_recording(tmp_path / "old.npz")
    assert old.decisions is None and old.tree_at("red", 0) == {}
    assert len(old) == 10 and old.robot("red").layer_at(0) == "FrontObstacleLeftTurn"


def test_a_newer_format_is_refused_in_one_line(tmp_path):
    recorded(tmp_path, 0.2)
    with np.load(tmp_path / "run.npz") as data:
        arrays = {k: data[k] for k in data.files if k != "meta"}
        meta = json.loads(str(data["meta"]))
    meta["version"] = FORMAT_VERSION + 1
    np.savez(tmp_path / "new.npz", meta=np.array(json.dumps(meta)), **arrays)
    with pytest.raises(ValueError, match=f"format {FORMAT_VERSION + 1}.*upgrade puckboard") as info:
        load_recording(tmp_path / "new.npz")
    assert "\n" not in str(info.value)


def test_damaged_decision_arrays_are_called_so(tmp_path):
    recorded(tmp_path, 0.2)
    with np.load(tmp_path / "run.npz") as data:
        arrays = {k: data[k] for k in data.files}
    arrays["tree"] = arrays["tree"][:-1]  # one tick short
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(ValueError, match="damaged puckboard recording.*'tree'"):
        load_recording(tmp_path / "bad.npz")


class Reader(Layer):
    """Reads a number, a pair of numbers and a text; applies when the number is positive."""

    reads = ("level", "label")

    def applies(self, frame):
        return (frame.value("level") or 0) > 0

    def command(self, frame):
        return WheelCommand(1.0, 1.0)


def test_any_key_a_layer_reads_is_kept_numbers_as_numbers_text_by_its_age(tmp_path):
    clock = {"t": 0.0}
    board = Blackboard(clock=lambda: clock["t"])
    ns = board.namespace("a")
    ctl = Controller([Reader(), Cruise(0.1)], name="arb")
    recorder = Recorder(["a"], controllers={"a": ctl}, capacity=16)
    ns.put("label", "hello", stamp=0.0)
    for k in range(40):  # past the capacity: the arrays grow
        clock["t"] = 0.1 * k
        ns.put("level", float(k % 3) - 1.0, stamp=clock["t"] - (0.05 if k % 2 else 0.0))
        ctl.tick(ns)
        recorder.sample(board)
    rec = recorder.close()
    rec = load_recording(rec.save(tmp_path / "r.npz"))
    d = rec.decisions
    assert d.keys == ("label", "level")
    levels = d.values["level"][:, 0, 0]
    np.testing.assert_array_equal(levels, [float(k % 3) - 1.0 for k in range(40)])
    assert "label" not in d.values and d.reads[0]["type"] == "str"
    np.testing.assert_allclose(d.age[:, 0, 0], 0.1 * np.arange(40), atol=1e-5)  # never updated
    np.testing.assert_allclose(
        d.age[:, 0, 1], [0.05 if k % 2 else 0.0 for k in range(40)], atol=1e-5
    )
    for k in range(40):
        expected = "Reader" if k % 3 == 2 else "Cruise"
        assert rec.robot("a").layer_at(k) == expected
        assert rec.tree_at("a", k)[expected] == "RUNNING"


def test_a_tick_on_stale_inputs_is_recorded_as_nobody_asked():
    from puckboard.behaviours import improved
    from puckboard.records import Ground, Proximity

    clock = {"t": 0.0}
    board = Blackboard(clock=lambda: clock["t"])
    ns = board.namespace("a")
    ns.declare("proximity", max_age=0.1)
    ctl = improved()
    recorder = Recorder(["a"], controllers={"a": ctl})
    ns.put("ground", Ground(np.ones(3), np.full(3, 1023.0)))
    for k in range(6):
        clock["t"] = 0.05 * k
        if k < 3:  # the IR sensors fall silent after three ticks
            ns.put("proximity", Proximity(np.full(8, 0.05), np.zeros(8)))
        ctl.tick(ns)
        recorder.sample(board)
    rec = recorder.close()
    layers = [rec.robot("a").layer_at(k) for k in range(6)]
    assert layers == ["Cruise"] * 5 + ["(stale inputs)"]
    assert rec.tree_at("a", 4)["Cruise"] == "RUNNING"
    assert set(rec.tree_at("a", 5).values()) == {"not ticked"}
    assert rec.decisions.fresh[4, 0].tolist() == [1, 1] and rec.decisions.fresh[5, 0].tolist() == [
        1,
        2,
    ]
    assert rec.decisions.age[5, 0, 1] == pytest.approx(0.15)
