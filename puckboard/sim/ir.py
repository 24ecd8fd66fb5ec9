"""Deprecated alias of :mod:`puckboard.ir_response`, kept for one release; import that instead."""

from .._moved import alias_module

alias_module(__name__, "puckboard.ir_response")
