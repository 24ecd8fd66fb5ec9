"""The graded seeds: drawn from the lecturer's secret, known to nobody else until revealed.

A challenge's practice seeds are public; its graded seeds must not be, or a controller
could be tuned to them. They are derived from a secret the lecturer keeps (a few words,
given as ``--secret WORD`` or in a file): a key is stretched from the secret and the
challenge's name (PBKDF2-HMAC-SHA256, so that guessing a weak secret from anything
published costs time), and each graded episode's seed is an HMAC of its cell's name and
its index under that key. The same secret gives the same seeds, on any machine, so a
grading resumes and re-grades on the same episodes; another secret gives others.

Nothing here prints a seed. What the output folder keeps is :func:`secret_check`, a tag
that tells the same secret from another and says nothing about the seeds.
"""

from __future__ import annotations

import hashlib
import hmac
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ChallengeError

if TYPE_CHECKING:
    from .spec import Challenge

__all__ = ["MIN_SECRET", "Secret", "read_secret"]

#: The shortest secret taken (characters): a short one is guessed.
MIN_SECRET = 8
#: PBKDF2 rounds: about 0.1 s once per command, a long time per guess.
_ROUNDS = 200_000


class Secret:
    """The lecturer's secret, stretched for one challenge. Never printed: its ``repr``
    says nothing, and only :meth:`check` (a tag) is ever written down."""

    def __init__(self, text: str, challenge: str) -> None:
        self._key = hashlib.pbkdf2_hmac(
            "sha256", text.encode("utf-8"), f"puckboard-challenge:{challenge}".encode(), _ROUNDS
        )

    def __repr__(self) -> str:
        return "Secret(...)"

    def _mac(self, message: str) -> bytes:
        return hmac.new(self._key, message.encode("utf-8"), hashlib.sha256).digest()

    def check(self) -> str:
        """A tag that is equal for equal secrets (of one challenge), and reveals nothing."""
        return self._mac("check").hex()[:32]

    def seeds(self, cell: str, count: int, avoid: range | tuple[int, ...] = ()) -> tuple[int, ...]:
        """``count`` distinct seeds for graded cell ``cell`` (31-bit, none in ``avoid``,
        the practice seeds)."""
        seeds: list[int] = []
        index = 0
        while len(seeds) < count:
            digest = self._mac(f"seed\0{cell}\0{index}")
            seed = int.from_bytes(digest[:4], "big") & 0x7FFFFFFF
            index += 1
            if seed not in seeds and seed not in avoid:
                seeds.append(seed)
        return tuple(seeds)

    def graded_seeds(self, challenge: Challenge) -> dict[str, tuple[int, ...]]:
        """Every graded cell's seeds, by cell name."""
        return {
            cell.name: self.seeds(cell.name, challenge.episodes, challenge.practice_seeds)
            for cell in challenge.graded
        }


def read_secret(word: str | None, file: Path | None, challenge: str) -> Secret:
    """The secret given as ``--secret WORD`` or in ``--secret-file FILE`` (its text,
    without the line end), refused in one line when missing, empty or short."""
    if word is not None and file is not None:
        raise ChallengeError("give the secret once: --secret WORD or --secret-file FILE")
    if file is not None:
        try:
            text = file.read_text(encoding="utf-8").strip()
        except (OSError, UnicodeDecodeError) as exc:
            raise ChallengeError(f"--secret-file {str(file)!r}: cannot read it: {exc}") from None
        where = f"the secret in {str(file)!r}"
    elif word is not None:
        text = word.strip()
        where = "--secret"
    else:
        raise ChallengeError(
            "grading needs the secret the graded seeds come from: --secret-file FILE (or "
            "--secret WORD); keep it, the same secret resumes and re-grades"
        )
    if not text:
        raise ChallengeError(f"{where} is empty; give a few words nobody will guess")
    if len(text) < MIN_SECRET:
        raise ChallengeError(
            f"{where} has {len(text)} characters; give at least {MIN_SECRET} (a few words, or "
            'python -c "import secrets; print(secrets.token_hex(16))") so that nobody can '
            "guess it and the graded seeds"
        )
    return Secret(text, challenge)
