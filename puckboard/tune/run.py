"""Run a study: draw parameters, score them on the design seeds, validate the best.

Each trial's parameters are drawn by Optuna's TPE sampler, seeded afresh for every
trial with the study's seed plus the trial's index (:func:`_sampler`): what a trial
draws then depends only on the trials finished before it, so the same command gives the
same trials, and a study interrupted and resumed gives the same trials as one that ran
through. The first trial of a new study is the controller as shipped (its own values,
where they lie in the ranges), so the best found is never worse on the design seeds
than the starting point.

A trial runs its design seeds in rounds (:func:`~puckboard.tune.objective.rounds`);
after each, the score so far is reported and Optuna's median pruner may stop a trial
behind the median of earlier trials at that round (never after the first round, whose
few seeds say little). The best complete trial is then run on the validation seeds,
which no trial saw.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..sweep.plan import seeds_text
from .objective import Cell, CellRate, Score, cell_rates, rounds, run_cells
from .space import Param, own_values
from .storage import finished_trials, open_study

__all__ = ["DEFAULT_ROUNDS", "TrialEvent", "TuneResult", "TuneSpec", "run_tune", "seeds_text"]

log = logging.getLogger(__name__)

#: Rounds the design seeds are cut into, the steps at which a trial may be pruned.
DEFAULT_ROUNDS = 4
#: Finished trials before the pruner judges any (it compares with their median).
PRUNE_AFTER_TRIALS = 4
_VALIDATION_ATTR = "puckboard.validation"


@dataclass(frozen=True)
class TuneSpec:
    """What a study tunes and on which episodes (the command that made it)."""

    scenes: tuple[Any, ...]
    controller: str
    params: tuple[Param, ...]
    seeds: range
    validate: range
    profiles: tuple[str, ...] = ()
    fixed: Mapping[str, Any] = field(default_factory=dict)
    rounds: int = DEFAULT_ROUNDS
    sampler_seed: int = 0

    def __post_init__(self) -> None:
        overlap = sorted(set(self.seeds) & set(self.validate))
        if overlap:
            raise ValueError(
                f"--seeds and --validate share {len(overlap)} seeds (first {overlap[0]}); "
                "validation must use seeds the tuning never saw, e.g. --seeds 0:20 "
                "--validate 20:40"
            )

    @property
    def cells(self) -> list[Cell]:
        return [Cell(s.name, p) for s in self.scenes for p in (self.profiles or ("",))]

    def command(self) -> dict[str, Any]:
        """Everything that decides a trial's score: a study resumed under another command
        would mix trials scored on different episodes."""
        return {
            "scenes": [s.name for s in self.scenes],
            "controller": self.controller,
            "params": [p.spec for p in self.params],
            "profiles": list(self.profiles),
            "fixed": dict(sorted(self.fixed.items())),
            "seeds": seeds_text(self.seeds),
            "rounds": self.rounds,
            "sampler_seed": self.sampler_seed,
        }


@dataclass(frozen=True)
class TrialEvent:
    """A trial that ended, for a progress display."""

    number: int
    finished: int
    total: int
    pruned: bool
    best_value: float | None
    best_number: int | None
    best_worst: float | None
    seconds_left: float | None


@dataclass
class TuneResult:
    """A study's trials, its best parameters and their design and validation rates."""

    spec: TuneSpec
    trials: list[dict[str, Any]]
    best: dict[str, Any] | None
    design: list[CellRate]
    validation: list[CellRate]
    ran: int = 0
    skipped: int = 0
    wall_s: float = 0.0
    study: Any = None

    @property
    def pruned(self) -> int:
        return sum(1 for t in self.trials if t["state"] == "pruned")

    def episodes(self) -> tuple[int, int]:
        """Design episodes run by all trials, and those pruning spared."""
        per_round = [
            len(r) * len(self.spec.cells) for r in rounds(self.spec.seeds, self.spec.rounds)
        ]
        ran = spared = 0
        for trial in self.trials:
            done = int(trial["rounds"])
            ran += sum(per_round[:done])
            spared += sum(per_round[done:])
        return ran, spared

    def overfit(self) -> list[Cell]:
        """Cells whose validation interval lies wholly below their design interval: the
        tuning fitted its seeds, not the robots."""
        design = {r.cell: r for r in self.design}
        return [
            v.cell
            for v in self.validation
            if v.cell in design and v.interval[1] < design[v.cell].interval[0]
        ]


def _sampler(seed: int) -> Any:
    import optuna

    return optuna.samplers.TPESampler(seed=seed, multivariate=True)


def _pruner() -> Any:
    import optuna

    return optuna.pruners.MedianPruner(n_startup_trials=PRUNE_AFTER_TRIALS, n_warmup_steps=1)


def _defaults(spec: TuneSpec) -> dict[str, Any]:
    """The controller's own values of the tuned parameters, when all lie in their ranges."""
    own = own_values(spec.controller)
    values = {}
    for param in spec.params:
        value = own.get(param.name)
        if isinstance(value, (int, float)) and param.low <= value <= param.high:
            values[param.name] = int(value) if param.integer else float(value)
    return values if len(values) == len(spec.params) else {}


def run_tune(
    spec: TuneSpec,
    trials: int,
    *,
    executor: Any,
    study_path: Path | None = None,
    episode_timeout: float | None = None,
    on_trial: Callable[[TrialEvent], None] | None = None,
) -> TuneResult:
    """Run trials until ``trials`` have finished (complete or pruned) in the study, then
    validate the best. A Ctrl-C raises :class:`~puckboard.tune.objective.Interrupted`
    (a :class:`KeyboardInterrupt`) with every finished trial kept in ``study_path``."""
    from optuna.trial import TrialState

    t0 = time.perf_counter()
    study = open_study(
        study_path, spec.command(), sampler=_sampler(spec.sampler_seed), pruner=_pruner()
    )
    done = len(finished_trials(study))
    skipped = done
    design_rounds = rounds(spec.seeds, spec.rounds)
    ran = 0
    while done < trials:
        study.sampler = _sampler(spec.sampler_seed + done)
        if done == 0 and not study.get_trials(states=(TrialState.WAITING,)):
            defaults = _defaults(spec)
            if defaults:
                study.enqueue_trial(defaults)
        trial = study.ask()
        values = {p.name: p.suggest(trial) for p in spec.params}
        try:
            pruned, rates, count = _evaluate(
                spec, trial, values, design_rounds, executor, episode_timeout
            )
        except BaseException:
            study.tell(trial, state=TrialState.FAIL)
            raise
        trial.set_user_attr("cells", [r.to_dict() for r in rates])
        trial.set_user_attr("rounds", count)
        if pruned:
            study.tell(trial, state=TrialState.PRUNED)
        else:
            study.tell(trial, Score.of(rates).value)
        done += 1
        ran += 1
        if on_trial is not None:
            on_trial(_event(study, trial.number, done, trials, pruned, ran, t0))
    result = _result(study, spec, ran=ran, skipped=skipped)
    if result.best is not None:
        result.validation = _validate(study, spec, result.best, executor, episode_timeout)
    result.wall_s = time.perf_counter() - t0
    return result


def _evaluate(
    spec: TuneSpec,
    trial: Any,
    values: Mapping[str, Any],
    design_rounds: Sequence[range],
    executor: Any,
    episode_timeout: float | None,
) -> tuple[bool, list[CellRate], int]:
    """Run the trial round by round; ``(pruned, rates so far, rounds run)``."""
    outcomes: list[Any] = []
    params = {**spec.fixed, **values}
    rates: list[CellRate] = []
    for step, seeds in enumerate(design_rounds):
        outcomes += run_cells(
            spec.scenes, spec.profiles, spec.controller, seeds, params,
            executor=executor, episode_timeout=episode_timeout,
        )  # fmt: skip
        rates = cell_rates(outcomes, spec.cells)
        trial.report(Score.of(rates).value, step)
        if step + 1 < len(design_rounds) and trial.should_prune():
            log.info("trial %d pruned after round %d", trial.number, step + 1)
            return True, rates, step + 1
    return False, rates, len(design_rounds)


def _event(
    study: Any, number: int, done: int, total: int, pruned: bool, ran: int, t0: float
) -> TrialEvent:
    best = _best(study)
    elapsed = time.perf_counter() - t0
    worst = None
    if best is not None:
        worst = Score.of([CellRate.from_dict(c) for c in best.user_attrs["cells"]]).worst
    return TrialEvent(
        number=number,
        finished=done,
        total=total,
        pruned=pruned,
        best_value=None if best is None else float(best.value),
        best_number=None if best is None else int(best.number),
        best_worst=worst,
        seconds_left=elapsed / ran * (total - done) if ran else None,
    )


def _best(study: Any) -> Any:
    """The complete trial with the highest score, the earliest of equals."""
    from optuna.trial import TrialState

    complete = [t for t in study.trials if t.state == TrialState.COMPLETE]
    if not complete:
        return None
    return max(complete, key=lambda t: (t.value, -t.number))


def _result(study: Any, spec: TuneSpec, *, ran: int, skipped: int) -> TuneResult:
    trials = []
    for t in finished_trials(study):
        trials.append(
            {
                "number": t.number,
                "state": t.state.name.lower(),
                "params": {_label(spec, k): v for k, v in t.params.items()},
                "value": t.value,
                "rounds": t.user_attrs.get("rounds", 0),
                "cells": t.user_attrs.get("cells", []),
            }
        )
    best = _best(study)
    design = [CellRate.from_dict(c) for c in best.user_attrs["cells"]] if best else []
    best_dict = None
    if best is not None:
        best_dict = {"number": best.number, "params": dict(best.params), "value": best.value}
    return TuneResult(spec, trials, best_dict, design, [], ran=ran, skipped=skipped, study=study)


def _label(spec: TuneSpec, name: str) -> str:
    return next((p.label for p in spec.params if p.name == name), name)


def _validate(
    study: Any, spec: TuneSpec, best: Mapping[str, Any], executor: Any, timeout: float | None
) -> list[CellRate]:
    """The best trial's rates on the validation seeds; kept in the study, so that a
    resumed study that found nothing better does not run them again."""
    key = {"trial": best["number"], "seeds": seeds_text(spec.validate)}
    kept = study.user_attrs.get(_VALIDATION_ATTR)
    if isinstance(kept, dict) and kept.get("key") == key:
        return [CellRate.from_dict(c) for c in kept["cells"]]
    params = {**spec.fixed, **best["params"]}
    outcomes = run_cells(
        spec.scenes, spec.profiles, spec.controller, spec.validate, params,
        executor=executor, episode_timeout=timeout,
    )  # fmt: skip
    rates = cell_rates(outcomes, spec.cells)
    study.set_user_attr(_VALIDATION_ATTR, {"key": key, "cells": [r.to_dict() for r in rates]})
    return rates
