"""The registry of IR sensor models: the contract a model meets, and the models by name.

Every module of this package but this one is a model and defines ``MODEL``; they are
found, and imported, the first time a model is asked for (see the package's docstring).
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from ...profile import RobotProfile
    from ..surfaces import Surfaces

__all__ = ["FloatArray", "IrModel", "IrSensors", "ir_model", "ir_model_names"]

#: The world's N×8 IR arrays, and a step's normals.
FloatArray = npt.NDArray[np.float64]


class IrSensors(Protocol):
    """One model's IR sensors, built for the robots whose profiles name it."""

    @property
    def robots(self) -> Sequence[int]:
        """The world's indices of those robots."""

    def sense(
        self,
        poses: Sequence[Sequence[float]],
        normals: FloatArray | None,
        distance: FloatArray,
        raw: FloatArray,
    ) -> None:
        """Write these robots' rows of ``distance`` (N×8, m) and ``raw`` for ``poses``
        (N [x, y, theta]); ``normals`` (N×8 standard normals) are the step's draws for
        the noise, ``None`` for a noise-free reading. Other rows are left as they are."""

    def recalibrate(
        self, i: int, poses: Sequence[Sequence[float]], distance: FloatArray, raw: FloatArray
    ) -> None:
        """Robot ``i`` (one of :attr:`robots`) re-measures its IR baselines at ``poses``,
        as the e-puck2 firmware does on request; a model without baselines does nothing."""


#: How a model is built: ``(profiles of every robot of the world, the robots that use
#: it, the world's surfaces, rays per sensor, the scene's IR noise σ)``.
Build = Callable[["Sequence[RobotProfile]", Sequence[int], "Surfaces", int, float], IrSensors]


@dataclass(frozen=True)
class IrModel:
    """One IR sensor model, as its module declares it (``MODEL``)."""

    #: The name a profile's ``prox_model`` gives.
    name: str
    #: What the model is, as a sentence continues "senses with ...".
    summary: str
    #: Whether a reading follows an IR response a calibration can measure (a physical
    #: sensor's), rather than being an exact distance.
    has_response: bool
    build: Build


_MODELS: dict[str, IrModel] = {}


def _models() -> dict[str, IrModel]:
    """Every model of this package, by name (its modules imported once, when first asked)."""
    if not _MODELS:
        here = Path(__file__).parent
        for info in sorted(pkgutil.iter_modules([str(here)]), key=lambda m: m.name):
            if info.name == "registry":
                continue
            module = importlib.import_module(f"{__package__}.{info.name}")
            model = getattr(module, "MODEL", None)
            if isinstance(model, IrModel):
                _MODELS[model.name] = model
    return _MODELS


def ir_model_names() -> tuple[str, ...]:
    """The names of every IR sensor model, sorted."""
    return tuple(sorted(_models()))


def ir_model(name: str) -> IrModel:
    """The IR sensor model called ``name``; a ``ValueError`` naming the known ones."""
    try:
        return _models()[name]
    except KeyError:
        known = ", ".join(ir_model_names())
        raise ValueError(
            f"unknown IR sensor model {name!r} (prox_model); use one of {known}"
        ) from None
