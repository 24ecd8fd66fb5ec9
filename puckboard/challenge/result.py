"""What a grading produced: the leaderboard's views, and how the run went."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .standings import Standing

if TYPE_CHECKING:
    from .spec import Challenge

__all__ = ["Grading"]


@dataclass
class Grading:
    """What a grading produced: the leaderboard's views and how the run went."""

    challenge: Challenge
    out: Path
    #: the view the leaderboard leads with: ``final`` once frozen, else ``latest``
    view: str
    standings: list[Standing]
    #: the latest view, where the final one leads and differs from it
    latest: list[Standing] | None = None
    final_at: str | None = None
    checked: int = 0
    ran: int = 0
    skipped: int = 0
    interrupted: bool = False
    terminated: bool = False
    wall_s: float = 0.0
    #: seconds each step took: the pre-flight checks, the graded episodes, the replays
    phase_s: dict[str, float] = field(default_factory=dict)
    new: list[str] = field(default_factory=list)
    #: the graded seeds, once revealed (``None`` before)
    seeds: dict[str, tuple[int, ...]] | None = None
    revealed_at: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The ``--json`` object: the leaderboard's rows in rank order, and the run."""
        out: dict[str, Any] = {
            "challenge": self.challenge.name,
            "title": self.challenge.title,
            "ranking": list(self.challenge.ranking),
            "cells": [c.name for c in self.challenge.graded],
            "view": self.view,
            "final_at": self.final_at,
            "rows": [s.to_dict() for s in self.standings],
            "latest": None if self.latest is None else [s.to_dict() for s in self.latest],
            "checked": self.checked,
            "ran": self.ran,
            "skipped": self.skipped,
            "interrupted": self.interrupted,
            "new": list(self.new),
            "revealed_at": self.revealed_at,
            "wall_s": self.wall_s,
            "phase_s": dict(self.phase_s),
        }
        if self.seeds is not None:
            out["seeds"] = {cell: list(s) for cell, s in self.seeds.items()}
        return out
