"""The held-out families: models a controller was not designed on, written as data.

A controller is designed on one model: its scene with plausible robots (``--variation
plausible``, the model the published bands are measured on). Ligot & Birattari's
*pseudo-reality* judges it on another model instead, and Jakobi's *envelope of noise*
asks how far the varied aspects may stray before it fails. Each :class:`Family` is one
such model, described by what it changes and nothing else:

* ``sets``: settings given fixed values (``--set NAME=VALUE``, as ``run`` takes them);
* ``scaled``: settings multiplied by a scale, each from the scene's own value (the noise
  levels: at ``scale`` 2, twice the scene's);
* ``variation``: how each episode's robots (and conditions) are drawn;
* ``scene``: a scene run instead of the one the controller was designed on.

A family with a ``grid`` is a continuous perturbation: its robustness radius is read off
the grid (:mod:`puckboard.transfer.radius`). The grid is declared here, before anything
runs, ordered outward from the design model (scale 1), and never chosen by the outcome.
``scale`` is the point of the grid reported as the family's held-out band.

A family whose setting the installed puckboard does not know is simply not listed.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

__all__ = [
    "DESIGN",
    "FAMILIES",
    "NOISE_SETTINGS",
    "PLAUSIBLE",
    "Family",
    "choose_families",
    "scene_value",
]

#: Name of the design model's band (not a family: the model the others are held out from).
DESIGN = "design"
#: The design model's variation: plausible robots, as the published bands.
PLAUSIBLE = "plausible"

#: The noise levels a noise family scales: the wheels', the IR's, the ground sensors' and
#: the gyro's. Start jitter is where a robot is put down, not what it senses or drives.
NOISE_SETTINGS = ("noise.wheel_speed", "noise.proximity", "noise.ground", "noise.gyro")


@dataclass(frozen=True)
class Family:
    """One held-out model: a name, one line on what it changes, and the changes.

    ``scale`` is the held-out point (the scale the family's band is measured at) and
    ``grid`` the scales its radius is read from, outward from 1 (the design model); a
    family without ``scaled`` settings has neither (``scale`` 1, no grid).
    """

    name: str
    what: str
    sets: Mapping[str, Any] = field(default_factory=dict)
    scaled: tuple[str, ...] = ()
    scale: float = 1.0
    grid: tuple[float, ...] = ()
    variation: str = PLAUSIBLE
    scene: str | None = None
    source: str = ""

    def __post_init__(self) -> None:
        if self.grid and not self.scaled:
            raise ValueError(f"family {self.name}: a grid needs scaled settings")
        if self.grid and (self.grid[0] != 1 or len(set(self.grid)) != len(self.grid)):
            raise ValueError(
                f"family {self.name}: a grid starts at 1 (the design model) and lists each "
                "scale once"
            )
        if self.grid and self.scale not in self.grid:
            raise ValueError(f"family {self.name}: its scale {self.scale} is not on its grid")

    @property
    def label(self) -> str:
        """How reports name the family's band: a scaled family with its scale
        (``noise ×2``)."""
        return f"{self.name} ×{self.scale:g}" if self.scaled else self.name

    @property
    def has_radius(self) -> bool:
        """Whether a robustness radius is read off this family's grid."""
        return bool(self.grid)

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "label": self.label,
            "what": self.what,
            "sets": dict(self.sets),
            "scaled": list(self.scaled),
            "scale": self.scale,
            "grid": list(self.grid),
            "variation": self.variation,
            "scene": self.scene,
            "source": self.source,
        }


def scene_value(scene: Any, name: str) -> float:
    """The scene's own value of a setting a family scales (``noise.proximity`` → the
    scene's proximity noise); ``KeyError`` for a setting that cannot be scaled."""
    group, _, key = name.partition(".")
    if group == "noise" and hasattr(scene.noise, key):
        return float(getattr(scene.noise, key))
    raise KeyError(f"{name} is not a setting a family can scale")


#: Every family, in the order reports list them. The noise grid doubles as Jakobi's
#: question (how far may the noise stray?): 1, 2, 3 and 4 times the scene's levels, the
#: issue's measured ×3 inside it, ×2 its held-out point.
FAMILIES: tuple[Family, ...] = (
    Family(
        name="noise",
        what="wheel, IR, ground and gyro noise at twice the scene's (radius: ×1 to ×4)",
        scaled=NOISE_SETTINGS,
        scale=2.0,
        grid=(1.0, 2.0, 3.0, 4.0),
        source="Jakobi 1997 (envelope of noise); ARGoS's e-puck wheels 5 %, Enki ±5 % "
        "against the scenes' 3 % (docs/scenarios.md)",
    ),
)


def choose_families(
    names: Sequence[str] | None, families: Sequence[Family] = FAMILIES
) -> tuple[Family, ...]:
    """The families named (each by its name, in the order given), or all of them; an
    unknown name is a ``ValueError`` that lists the names there are."""
    if not names:
        return tuple(families)
    by_name = {f.name: f for f in families}
    chosen = []
    for name in names:
        if name not in by_name:
            close = difflib.get_close_matches(name, list(by_name), n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ValueError(
                f"--families: no family {name!r}{hint}; families: {', '.join(by_name)}"
            )
        if by_name[name] in chosen:
            raise ValueError(f"--families: {name!r} is listed twice")
        chosen.append(by_name[name])
    return tuple(chosen)
