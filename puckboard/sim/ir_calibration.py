"""What an e-puck makes of its IR sensors' responses: calibrated values, then distances.

The rays model (:mod:`.proximity`) computes what each photodiode reads, ambient baseline
(≈67 on the table's scale) included. A real e-puck2 does not send that: at start-up its
firmware measures every sensor with nothing in front of it and from then on sends the
reading minus that baseline, clamped at 0 (``get_calibrated_prox``). What the
calibration leaves over is the sensor's ``ir_offset``. So a simulated sensor reports

    calibrated = clip(response − gain·T(∞) + offset, 0, 4095)

as its ``raw`` value, what a real e-puck2 sends over sercom or Wi-Fi, and its distance
through the one conversion every backend uses
(:func:`puckboard.ir_response.distance_from_calibrated`): the distance then carries the
curve's saturation near 0 and the noise that grows with distance, as on the robot, and
a reading at or below the curve's value at ``prox_max_distance`` is "nothing"
(``prox_range``).

The conversion uses the numbers of the robot as built: the curve itself is nominal (no
gain: nothing on a robot knows its gains), and ``prox_max_distance``, where a robot's
sensors stop telling anything from nothing, is a property of the robot a plausible draw
varies, so a drawn robot is the same robot when it is rebuilt with ``--set``.

Robots sensing with V-REP's cones (:mod:`.cone`) report exact distances and are left to
that model.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..ir_response import RAW_MAX, cutoff_value, distances_from_calibrated
from ..profile import RobotProfile

__all__ = ["IrCalibration"]

FloatArray = npt.NDArray[np.float64]


class IrCalibration:
    """The calibration and distance conversion of N robots' IR sensors.

    ``baseline`` (N×8) is each sensor's response to nothing (its gain times the table's
    far value, :attr:`.proximity.ProximitySensors.baseline_raw`).
    """

    def __init__(self, profiles: Sequence[RobotProfile], baseline: FloatArray) -> None:
        self._baseline = baseline
        #: N×8 raw units each sensor's calibration leaves over (:meth:`recalibrate` sets it)
        self.offset = np.array([p.ir_offset for p in profiles], dtype=float).reshape(-1, 8)
        self._cutoff = np.array([cutoff_value(p.prox_max_distance) for p in profiles])[:, None]
        self._lowest_cutoff = float(self._cutoff.min()) if len(profiles) else 0.0
        self._nothing = np.array([p.prox_range for p in profiles], dtype=float)[:, None]
        self._offsets_changed()

    def _offsets_changed(self) -> None:
        self._shift = self.offset - self._baseline
        self._any_offset = bool(self.offset.any())
        # with nothing near anyone and no noise every robot reads its offsets, clamped
        self._quiet_raw = np.clip(self.offset, 0.0, RAW_MAX)
        self._quiet_distance = distances_from_calibrated(
            self._quiet_raw, self._cutoff, self._nothing
        )

    def apply(self, raw: FloatArray, distance: FloatArray) -> None:
        """Turn the responses in ``raw`` (N×8, in place) into calibrated values and write
        the distances they convert to into ``distance``."""
        raw += self._shift
        # two ufuncs: np.clip's Python wrapper costs more than the clamping itself
        np.maximum(raw, 0.0, out=raw)
        np.minimum(raw, RAW_MAX, out=raw)
        distances_from_calibrated(raw, self._cutoff, self._nothing, out=distance)

    def apply_to_nothing(
        self, raw: FloatArray, distance: FloatArray, noise: FloatArray | None
    ) -> None:
        """:meth:`apply` for a step in which no sensor sees anything, each response being
        its baseline times ``1 + noise`` (``noise``: N×8 relative, or None).

        Most steps of a line-following run; the response minus the baseline is then
        ``baseline·noise``, computed as that, and the conversion is needed only where a
        value reaches a cut-off (a large offset can make one).
        """
        if noise is None:
            raw[:] = self._quiet_raw
            distance[:] = self._quiet_distance
            return
        np.multiply(self._baseline, noise, out=raw)
        if self._any_offset:
            raw += self.offset
        np.maximum(raw, 0.0, out=raw)
        if raw.max() > self._lowest_cutoff:  # rarely: the clamp at full scale, the conversion
            np.minimum(raw, RAW_MAX, out=raw)
            distances_from_calibrated(raw, self._cutoff, self._nothing, out=distance)
        else:
            distance[:] = self._nothing

    def recalibrate(
        self, i: int, response: FloatArray, raw: FloatArray, distance: FloatArray
    ) -> None:
        """Robot ``i`` re-measures its baselines now, ``response`` (8 values) being what
        its sensors read (noise-free: the firmware averages many samples), as the e-puck2
        firmware does on request: from now on it subtracts those. In free space that
        zeroes the offsets; an object in front of a sensor blinds it later. ``raw`` and
        ``distance`` (N×8) get robot ``i``'s readings at this pose after calibrating:
        0, and nothing seen."""
        self.offset[i] = self._baseline[i] - response
        self._offsets_changed()
        raw[i] = 0.0
        distance[i] = self._nothing[i]
