"""The secret's seeds, and a class's folder: found, named, known by content, kept."""

from __future__ import annotations

import pytest

from puckboard.challenge import parse_challenge
from puckboard.challenge.seeds import Secret, read_secret
from puckboard.challenge.submissions import History, find_submissions
from puckboard.errors import ChallengeError

CHALLENGE = """
name = "mini"
[[practice.cells]]
name = "lf"
scene = "line-follow"
[graded]
episodes = 5
[[graded.cells]]
name = "a"
scene = "line-follow"
[[graded.cells]]
name = "b"
scene = "line-follow"
duration = 5
"""


def test_the_same_secret_gives_the_same_seeds_and_another_others():
    challenge = parse_challenge(CHALLENGE, source="mini.toml")
    one = Secret("correct horse battery", "mini").graded_seeds(challenge)
    assert one == Secret("correct horse battery", "mini").graded_seeds(challenge)
    other = Secret("correct horse battery!", "mini").graded_seeds(challenge)
    assert set(one) == {"a", "b"} and all(len(s) == 5 for s in one.values())
    every = [s for seeds in one.values() for s in seeds]
    assert len(set(every)) == 10  # distinct, in and across cells
    assert not set(every) & set(challenge.practice_seeds)
    assert all(0 <= s < 2**31 for s in every)
    assert not set(every) & {s for seeds in other.values() for s in seeds}
    # the tag tells secrets apart, and the seeds are not in it nor in the object's text
    secret = Secret("correct horse battery", "mini")
    assert (
        secret.check()
        == Secret("correct horse battery", "mini").check()
        != Secret("x" * 9, "mini").check()
    )
    assert repr(secret) == "Secret(...)"
    assert not any(str(s) in secret.check() for s in every)


@pytest.mark.parametrize(
    ("word", "content", "said"),
    [
        (None, None, "grading needs the secret the graded seeds come from: --secret-file FILE"),
        ("", None, "--secret is empty"),
        ("short", None, "--secret has 5 characters; give at least 8"),
        (None, "\n", "is empty"),
    ],
)
def test_a_missing_empty_or_short_secret_is_one_line(tmp_path, word, content, said):
    file = None
    if content is not None:
        file = tmp_path / "secret.txt"
        file.write_text(content)
    with pytest.raises(ChallengeError) as refused:
        read_secret(word, file, "mini")
    assert said in str(refused.value) and "\n" not in str(refused.value)


def test_submissions_are_files_or_folders_of_one_file(tmp_path):
    (tmp_path / "alice.py").write_text("A = 1\n")
    (tmp_path / "bob").mkdir()
    (tmp_path / "bob" / "controller.py").write_text("B = 1\n")
    (tmp_path / "_reference.py").write_text("R = 1\n")
    (tmp_path / "notes.txt").write_text("not a submission\n")
    found = find_submissions(tmp_path)
    assert [(s.name, s.path.name) for s in found] == [
        ("alice", "alice.py"),
        ("bob", "controller.py"),
    ]
    assert found[0].version.startswith("alice@") and len(found[0].digest) == 64


@pytest.mark.parametrize(
    ("layout", "said"),
    [
        (
            {"Alice.py": "A = 1", "alice.py": "A = 2"},
            "two submissions have the same name: Alice.py and alice.py",
        ),
        (
            {"alice.py": "A = 1", "alice/x.py": "A = 2"},
            "two submissions have the same name: alice/x.py and alice.py",
        ),
        (
            {"carl/a.py": "1", "carl/b.py": "2"},
            "holds 2 .py files (a.py, b.py); a submission is one file",
        ),
        ({"readme.txt": "hi"}, "holds no submission"),
    ],
)
def test_a_folder_that_cannot_be_graded_is_one_line(tmp_path, layout, said):
    for name, text in layout.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    if any(n != n.lower() for n in layout) and len(list(tmp_path.iterdir())) < len(layout):
        pytest.skip("this file system does not tell names apart by case")
    with pytest.raises(ChallengeError) as refused:
        find_submissions(tmp_path)
    assert said in str(refused.value)


def test_a_missing_folder_is_one_line(tmp_path):
    with pytest.raises(ChallengeError, match="the submissions folder .* does not exist"):
        find_submissions(tmp_path / "nowhere")


def test_history_keeps_every_version_and_a_frozen_final_view(tmp_path):
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "alice.py").write_text("V = 1\n")
    history = History(tmp_path / "out")
    first, new = history.add(find_submissions(folder)[0])
    assert new and not history.add(find_submissions(folder)[0])[1]  # same content: known
    history.freeze(history.latest())
    (folder / "alice.py").write_text("V = 2\n")
    second, new = history.add(find_submissions(folder)[0])
    assert new and second.digest != first.digest
    history.save()
    again = History(tmp_path / "out")  # read back
    assert [v.digest for v in again.versions["alice"]] == [first.digest, second.digest]
    assert again.latest()["alice"].digest == second.digest
    assert again.final_versions()["alice"].digest == first.digest  # keep playing: final kept
    assert again.file_of(first).read_text() == "V = 1\n"  # the graded copy, as it was
    assert again.file_of(first) != again.file_of(second)
