"""Challenge files: every field read and checked, each mistake refused in one line."""

from __future__ import annotations

import pytest

from puckboard.challenge import challenge_names, load_challenge, parse_challenge
from puckboard.challenge.spec import RANKING_KEYS
from puckboard.errors import ChallengeError

MINIMAL = """
name = "mini"
[[practice.cells]]
name = "lf"
scene = "line-follow"
[graded]
episodes = 2
[[graded.cells]]
name = "bend"
scene = "two-robot-pass-bend"
profile = "epuck"
variation = "plausible"
"""


def test_the_shipped_example_reads_and_says_what_it_grades():
    assert "pass" in challenge_names()
    challenge = load_challenge("pass")
    assert challenge.factory == "make_controller"
    assert [c.name for c in challenge.graded] == [
        "bend",
        "new tracks",
        "lab conditions",
        "slow link",
    ]
    assert challenge.baselines == ("stock", "improved", "robust")
    assert challenge.ranking == ("worst_cell_success", "success", "median_progress")
    slow = challenge.cell("slow link")
    # the link's slow end, in whole physics steps: what transfer's link family runs
    assert slow.parameters["control.period"] == pytest.approx(0.1)
    assert (
        slow.parameters["robot.profile"] == "epuck" and slow.parameters["variation"] == "plausible"
    )
    assert (
        slow.describe()
        == "two-robot-pass · profile epuck · variation plausible · link bluetooth-sercom"
    )
    assert challenge.practice_seeds == range(3)


def test_defaults_and_a_scene_file_beside_the_challenge(tmp_path):
    (tmp_path / "short.toml").write_text(
        (load_challenge_scene_text() + "\n").replace('name = "line-follow"', 'name = "short"')
    )
    text = MINIMAL.replace('scene = "line-follow"', 'scene = "short.toml"')
    (tmp_path / "mine.toml").write_text(text)
    challenge = load_challenge(tmp_path / "mine.toml")
    assert challenge.practice[0].scene.name == "short"
    assert challenge.episodes == 2
    # no limit given: the longest graded episode (120 s) and 30 s more
    assert challenge.episode_timeout == 150.0
    assert challenge.check_timeout == 30.0 and challenge.memory_mib == 1024
    assert challenge.baselines == ()


def load_challenge_scene_text() -> str:
    from puckboard.scenario.scenefile import scene_path

    return scene_path("line-follow").read_text(encoding="utf-8")


#: (what to change in MINIMAL, into what) -> what the one line says
MISTAKES = [
    (
        ("[graded]", "[graded]\nepisodez = 3"),
        "graded.episodez: unknown key; did you mean 'episodes'?",
    ),
    (
        ('scene = "two-robot-pass-bend"', 'scene = "two-robot-pass-bent"'),
        "graded.cells[0].scene: unknown scene 'two-robot-pass-bent'",
    ),
    (
        ('variation = "plausible"', 'variation = "likely"'),
        "graded.cells[0].variation: expected one of none, plausible, reality-gap, got 'likely'",
    ),
    (('profile = "epuck"', 'profile = "epuk"'), "graded.cells[0].profile: unknown robot profile"),
    (
        ("[graded]", '[ranking]\norder = ["fastest"]\n[graded]'),
        "ranking.order: unknown name 'fastest'; use worst_cell_success",
    ),
    (
        ("[graded]", '[ranking]\nbaselines = ["mine.py:make"]\n[graded]'),
        "ranking.baselines: unknown name 'mine.py:make'; use stock, improved, robust",
    ),
    (
        ("[graded]", "[limits]\nepisode_timeout = 0\n[graded]"),
        "limits.episode_timeout: expected a number >= 1 (s), got 0.0",
    ),
    (("episodes = 2", "episodes = 2.5"), "graded.episodes: expected a whole number, got 2.5"),
    (('name = "mini"', 'name = "a b"'), "name: expected a short name"),
    (
        ('profile = "epuck"', 'set = { "noise.proximty" = 0.1 }'),
        "set.noise.proximty: unknown parameter 'noise.proximty'",
    ),
    (
        ('profile = "epuck"', 'link = "carrier-pigeon"'),
        "graded.cells[0].link: expected one of coppeliasim-sync",
    ),
    (
        ("episodes = 2", "episodes = 2\n[[graded.cells]]\nname = 'bend'\nscene = 'line-follow'"),
        "graded.cells[1].name: 'bend' is used twice",
    ),
]


@pytest.mark.parametrize(("change", "said"), MISTAKES)
def test_a_mistake_is_one_line_naming_the_file_the_table_and_the_fix(change, said):
    old, new = change
    assert old in MINIMAL
    with pytest.raises(ChallengeError) as refused:
        parse_challenge(MINIMAL.replace(old, new, 1), source="mine.toml")
    message = str(refused.value)
    assert message.startswith("mine.toml: ") and said in message, message
    assert "\n" not in message


def test_a_graded_cell_set_twice_under_two_names_is_refused():
    twice = MINIMAL + (
        '[[graded.cells]]\nname = "again"\nscene = "two-robot-pass-bend"\n'
        'profile = "epuck"\nvariation = "plausible"\n'
    )
    with pytest.raises(
        ChallengeError, match="graded.cells: cells 'bend' and 'again' are the same cell"
    ):
        parse_challenge(twice, source="mine.toml")


def test_identity_names_what_changes_the_graded_episodes():
    challenge = parse_challenge(MINIMAL, source="a.toml")
    more = parse_challenge(MINIMAL.replace("episodes = 2", "episodes = 3"), source="a.toml")
    ranked = parse_challenge(MINIMAL + '[ranking]\norder = ["success"]\n', source="a.toml")
    assert challenge.differences(more.identity()) == ["episodes 3 there, 2 here"]
    assert challenge.differences(ranked.identity()) == []  # the rule may change: nothing reruns
    assert set(RANKING_KEYS) >= set(ranked.ranking)


def test_a_missing_or_unreadable_challenge_is_one_line(tmp_path):
    with pytest.raises(ChallengeError, match="no challenge 'passs': name a shipped one"):
        load_challenge("passs")
    with pytest.raises(ChallengeError, match="cannot read challenge file"):
        load_challenge(tmp_path / "nowhere.toml")
    (tmp_path / "broken.toml").write_text("name = [")
    with pytest.raises(ChallengeError, match="broken.toml: not valid TOML"):
        load_challenge(tmp_path / "broken.toml")
