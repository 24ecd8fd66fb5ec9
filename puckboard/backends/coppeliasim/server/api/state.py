"""The served state every group of ``sim.*`` functions acts on, and how a handle names it.

The groups (:mod:`.scene_tree`, :mod:`.poses`, :mod:`.sensors` ...) are mixins of
:class:`~puckboard.backends.coppeliasim.server.simapi.SimApi`; :class:`ServedState` is
their common base, so that each group is type-checked against the one set of attributes
``SimApi.__init__`` creates, and so that the two look-ups every group needs — the object
a client's handle names (:meth:`ServedState._object`) and where that object is now
(:meth:`ServedState.world_frame`) — exist once.

A call that cannot be served raises :class:`ApiError`; its message goes back to the
client as ``err``, in CoppeliaSim's wording where CoppeliaSim has one.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..frames import Frame, rotation_z
from ..objects import DUMMY, SceneObjects, ServedObject

if TYPE_CHECKING:
    import numpy as np

    from .....scenario.scene import Scene
    from .....sim.world import World

__all__ = ["STEP_PENDING", "ApiError", "ServedState", "Signals", "StepPending", "kind_words"]

#: A handle's flag bits (``sim.handleflag_*``) live above this.
_HANDLE_MASK = 0x000FFFFF


def kind_words(kind: str) -> str:
    """An object kind as a refusal names it: ``a proximity sensor``, ``a joint``."""
    words = kind.replace("_", " ")
    return f"{'an' if words[0] in 'aeiou' else 'a'} {words}"


class ApiError(Exception):
    """A call that cannot be served; the message goes back to the client as ``err``."""


class StepPending:
    """Returned by ``sim.step`` when the client must wait for the simulation to advance."""


STEP_PENDING = StepPending()


@dataclass
class Signals:
    """CoppeliaSim's signals: three separate name spaces, shared by every client and
    cleared when the simulation stops (a client-set signal lives for one run)."""

    string: dict[str, str | bytes] = field(default_factory=dict)
    int32: dict[str, int] = field(default_factory=dict)
    float: dict[str, float] = field(default_factory=dict)

    def clear(self) -> None:
        self.string.clear()
        self.int32.clear()
        self.float.clear()


class ServedState:
    """One served world and its objects, as the served functions see them.

    Declares what ``SimApi.__init__`` creates; only the server thread calls into it, so
    nothing here is locked.
    """

    scene: Scene
    seed: int
    realtime: bool
    #: Whether the e-puck's script has puckboard's functions (see ``SimApi``).
    script_functions: bool
    _world_class: type[World]
    world: World
    objects: SceneObjects
    #: Wheel target velocities (rad/s), one row per robot.
    targets: np.ndarray
    running: bool
    paused: bool
    signals: Signals
    #: Where the dummies are (clients may move them); restored on stop.
    dummy_frames: dict[int, Frame]
    _visibility: dict[int, int]
    _int_params: dict[int, int]

    def _object(self, handle: int, func: str, kind: str | None = None) -> ServedObject:
        obj = self.objects.get(handle & _HANDLE_MASK if handle > 0 else handle)
        if obj is None:
            raise ApiError(f"{func}: object does not exist (handle {handle})")
        if kind is not None and obj.kind != kind:
            raise ApiError(
                f"{func}: object {obj.name} (handle {handle}) is {kind_words(obj.kind)}, "
                f"not {kind_words(kind)}"
            )
        return obj

    def world_frame(self, obj: ServedObject) -> Frame:
        """Where ``obj`` is now, in the world."""
        if obj.model and obj.robot is not None:
            x, y, theta = self.world.poses[obj.robot].tolist()
            return Frame.planar(x, y, theta, self.world.actual[obj.robot].wheel_radius)
        if obj.kind == DUMMY:
            return self.dummy_frames[obj.handle]
        local = obj.local
        if obj.part in ("left_wheel", "right_wheel") and obj.robot is not None:
            angle = float(self.world.encoders[obj.robot, obj.index])
            local = Frame(local.rotation @ rotation_z(angle), local.position)
        if obj.parent is None:
            return local
        parent = self.objects.get(obj.parent)
        assert parent is not None
        return self.world_frame(parent).compose(local)
