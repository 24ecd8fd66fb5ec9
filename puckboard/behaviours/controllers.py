"""Deprecated alias of :mod:`puckboard.behaviours.presets`, kept for one release; import that instead."""

from .._moved import alias_module

alias_module(__name__, "puckboard.behaviours.presets")
