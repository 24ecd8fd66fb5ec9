"""The served ``sim.*`` functions, one module per group of CoppeliaSim's manual.

Each group is a mixin of :class:`~puckboard.backends.coppeliasim.server.simapi.SimApi`,
which composes them over one world and holds the *one* dispatch table: a method here is
reachable by a client only because that table names it, never by its Python name.

* :mod:`.names` — CoppeliaSim's ``sim`` namespace: its function names and constants;
* :mod:`.checks` — the argument checks every call passes before anything runs;
* :mod:`.state` — the state the groups share, the handle lookup, the error a call answers;
* :mod:`.scene_tree` — handles, names, aliases, parents and children;
* :mod:`.poses` — where an object is, in any frame, and placing dummies;
* :mod:`.joints` — the wheel joints' targets, angles and speeds;
* :mod:`.sensors` — proximity sensors and vision sensors (light sensor, camera);
* :mod:`.parameters` — the object and simulation parameters that are served;
* :mod:`.signals` — string, integer and float signals;
* :mod:`.simulation` — start, pause, stop, time, stepping and log messages;
* :mod:`.scripts` — the e-puck's child script: sense-all and set-wheels in one call.
"""
