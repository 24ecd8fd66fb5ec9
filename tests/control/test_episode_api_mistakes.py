"""``run_episode`` called the ways a student gets it wrong: each says, in the student's
words, what to pass instead (issue 35, item 17)."""

from __future__ import annotations

import pytest

from puckboard.behaviours import Cruise, LineFollow, improved
from puckboard.control.episode import run_episode


def test_a_controller_object_where_its_factory_belongs():
    with pytest.raises(TypeError) as caught:
        run_episode("line-follow", controller=improved())
    assert str(caught.value).startswith(
        "got the controller 'improved' itself where its factory belongs"
    )
    assert "controller=make rather than controller=make()" in str(caught.value)


def test_a_list_of_layers_where_a_factory_belongs():
    with pytest.raises(TypeError, match=r"^got a list of layers where a controller factory"):
        run_episode("line-follow", controller=[LineFollow(), Cruise()])


def test_a_misspelt_keyword_names_the_one_meant():
    with pytest.raises(TypeError) as caught:
        run_episode("line-follow", seeed=3)
    assert str(caught.value).startswith("unexpected keyword seeed=3 (did you mean seed=?); ")


@pytest.mark.parametrize("seed", [-3, 1.5, "3"])
def test_a_seed_numpy_cannot_use_is_refused_in_words(seed):
    with pytest.raises(ValueError) as caught:
        run_episode("line-follow", seed=seed)
    assert str(caught.value) == f"seed must be a whole number ≥ 0, got {seed!r}"


def test_a_backend_option_still_reaches_the_backend():
    result = run_episode("line-follow", duration=0.1, ir_rays=3)  # World's own option
    assert result.sim_time_s == pytest.approx(0.1)
