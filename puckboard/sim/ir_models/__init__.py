"""The IR sensor models, by name: each robot's profile names one (``prox_model``).

As IR-SIM picks a sensor class by name from a table, the world builds, once, each model its
robots' profiles name, for those robots, and asks every model to
:meth:`~.registry.IrSensors.sense` each step. A model is one module of this package that defines
``MODEL``, an :class:`~.registry.IrModel`: its name, what it is, whether it has an IR response a
calibration can measure, and how it is built. Adding a model is adding that one module; nothing
else in puckboard names it (the profile names it, the world finds it here, ``puckboard calibrate``
asks it whether there is a response to measure).

The shipped models: ``rays`` (:mod:`.rays`, the physical e-puck: rays through the
calibrated response) and ``cone`` (:mod:`.cone`, V-REP's exact cones). A model writes
only its own robots' rows of the world's N×8 IR arrays, so the models of a mixed world
may sense in any order.
"""

from .registry import IrModel, IrSensors, ir_model, ir_model_names

__all__ = ["IrModel", "IrSensors", "ir_model", "ir_model_names"]
