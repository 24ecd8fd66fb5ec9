"""Deprecated alias of :mod:`puckboard.viz.recording`, kept for one release; import that instead."""

from ._moved import alias_module

alias_module(__name__, "puckboard.viz.recording")
