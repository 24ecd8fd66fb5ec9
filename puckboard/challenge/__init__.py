"""Class challenges: students' controllers graded on cells and seeds they never saw.

A challenge file (:mod:`.spec`) names a practice set and a graded set of cells; the graded
seeds come from the lecturer's secret (:mod:`.seeds`). ``puckboard challenge check``
runs a submission's pre-flight check and practice episodes (:mod:`.check`);
``puckboard challenge grade`` grades a folder of submissions, each in processes of its
own, resumably (:mod:`.grade`), and writes the leaderboard (:mod:`.leaderboard`,
:mod:`.page`).
"""

from __future__ import annotations

from .spec import Cell, Challenge, challenge_names, load_challenge, parse_challenge

__all__ = ["Cell", "Challenge", "challenge_names", "load_challenge", "parse_challenge"]
