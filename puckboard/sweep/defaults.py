"""What every experiment on the sweep machinery runs when not told otherwise.

The command line, the Python API and the benchmarks read these, so a default is said
once. Kept apart from the machinery and light (no numpy): the command line shows them in
its help while it builds its parser, before numpy may be imported (:mod:`.signals`).
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_SCENARIO",
    "JOINT_SEEDS",
    "SENSITIVITY_SEEDS",
    "TRANSFER_SEEDS",
    "TUNE_TRIALS",
]

#: The scene an experiment runs when none is named.
DEFAULT_SCENARIO = "two-robot-pass"

#: A transfer report's seeds per model (``--seeds`` as written): seeds none of the
#: shipped controllers was designed or validated on (robust: 0-199 design, 200-399 the
#: published bands), as many as keep the flagship report (docs/transfer.md) within five
#: minutes on two cores.
TRANSFER_SEEDS = "400:404"

#: A one-at-a-time sensitivity analysis's seeds per value: a whole profile (the physical
#: e-puck's 16 fields × 7 values, about 2,000 episodes) of one controller in about six
#: minutes on two cores, at the two-robot pass's measured 6 episodes/s (docs/simulator.md).
SENSITIVITY_SEEDS = "0:20"

#: Seeds (plausible robots) per controller and profile of a joint sensitivity analysis:
#: enough that a number moving the tutorial controller's rate is clear (docs/sweeps.md
#: says what N buys), the whole flagship analysis in about five minutes on two cores.
JOINT_SEEDS = "0:300"

#: Finished trials a tuning study wants.
TUNE_TRIALS = 20
