"""The embedded 2D e-puck simulator: the default backend, no external program needed.

The simulator knows no controller: it takes wheel speeds and gives sensor readings. The
engine's entry point is :class:`~puckboard.sim.world.World`; the scenes it is built from
live in :mod:`puckboard.scenario`.
"""
