"""A controller a scene file names is not on the command line: a bad one names the file
and the robot, where it used to say only "unknown controller 'improvd'"."""

from __future__ import annotations

import pytest

from puckboard.control.episode import Episode
from puckboard.errors import SceneError
from puckboard.scenario import load_scene


def test_a_bad_controller_in_a_scene_file_names_the_file_and_the_robot(tmp_path):
    path = tmp_path / "my_scene.toml"
    path.write_text(
        'name = "mine"\n[[robots]]\nname = "lefty"\nx = 0.0\ny = 0.0\ntheta = 0.0\n'
        'controller = "improvd"\n',
        encoding="utf-8",
    )
    with pytest.raises(SceneError) as caught:
        Episode(load_scene(path), backend="fake")
    message = str(caught.value)
    assert message.startswith(f"{path}: robot 'lefty': unknown controller 'improvd'"), message
