"""Robot profiles: the e-puck's geometry and limits as data, how sure each number is, and
your own robot as a file.

* :mod:`~puckboard.profile.model`: :class:`RobotProfile`, the one record of a robot model,
  and its unit conversions.
* :mod:`~puckboard.profile.shipped`: the shipped profiles (``epuck``, ``e-puck1``,
  ``epuck-vrep``), every number with its source.
* :mod:`~puckboard.profile.setting_names`: the names numbers are set by (``prox_radius.side``),
  checked against physical sense; :func:`apply_overrides`.
* :mod:`~puckboard.profile.uncertainty`: plausible ranges with their sources, plausible
  robots drawn from them (:func:`draw`), :func:`profile_values`.
* :mod:`~puckboard.profile.files`: profile files (``--profile my-epuck.toml``).
"""

from __future__ import annotations

from .files import load_profile_file, profile_from_data, profile_to_data, resolve_profile
from .model import NO_DETECTION_DISTANCE, RobotProfile, SensorPose
from .setting_names import PROX_GROUPS, apply_overrides, check_setting, check_value
from .shipped import EPUCK, EPUCK1, EPUCK2, EPUCK_VREP, PROFILES, get_profile, profile_names
from .uncertainty import Range, draw, profile_values, uncertainty, variation_rng

__all__ = [
    "EPUCK",
    "EPUCK1",
    "EPUCK2",
    "EPUCK_VREP",
    "NO_DETECTION_DISTANCE",
    "PROFILES",
    "PROX_GROUPS",
    "Range",
    "RobotProfile",
    "SensorPose",
    "apply_overrides",
    "check_setting",
    "check_value",
    "draw",
    "get_profile",
    "load_profile_file",
    "profile_from_data",
    "profile_names",
    "profile_to_data",
    "profile_values",
    "resolve_profile",
    "uncertainty",
    "variation_rng",
]
