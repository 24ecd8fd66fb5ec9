"""The scene tree: ``sim.getObject`` and its kin — handles, names, aliases, the hierarchy.

A controller written for CoppeliaSim finds its robot by the stock model's names
(``ePuck_leftJoint#0``) or by a CoppeliaSim 4.3+ alias path (``/ePuck[1]/leftJoint``);
both resolve against the served object tree (:mod:`..objects`), and every alias option of
``sim.getObjectAlias`` answers as CoppeliaSim's does, so scene-walking code runs unchanged.
"""

from __future__ import annotations

from typing import Any

from ..clients import ClientState
from ..objects import OBJECT_TYPES, ObjectNotFound
from .names import CONSTANTS as _C
from .names import HANDLE_ALL, HANDLE_SCENE
from .state import ApiError, ServedState

__all__ = ["SceneTreeFunctions"]


class SceneTreeFunctions(ServedState):
    """``sim.getObject*``, ``sim.isHandle``, ``sim.getModelProperty``: the tree, read-only."""

    def get_object(self, client: ClientState, path: str, options: dict[str, Any]) -> list[Any]:
        index = options.get("index", 0)
        if isinstance(index, bool) or not isinstance(index, int):
            raise ApiError("sim.getObject: options.index must be an integer")
        try:
            return [self.objects.resolve(path, index).handle]
        except ObjectNotFound as exc:
            if options.get("noError") is True:
                return [-1]
            raise ApiError(f"sim.getObject: {exc}") from None

    def get_object_handle(self, client: ClientState, name: str) -> list[Any]:
        try:
            return [self.objects.resolve(name).handle]
        except ObjectNotFound as exc:
            raise ApiError(f"sim.getObjectHandle: {exc}") from None

    def get_object_alias(self, client: ClientState, handle: int, options: int) -> list[Any]:
        obj = self._object(handle, "sim.getObjectAlias")
        objs = self.objects
        if options == -1:
            return [obj.alias]
        if options == 0:
            return [objs.alias_with_order(obj)]
        if options == 1:
            return [objs.alias_path(obj)]
        if options in (2, 5):
            return [objs.full_path(obj)]
        if options == 3 and objs.alias_is_unique(obj):
            return [obj.alias]
        if options in (3, 4):
            return [f"{obj.alias}__{obj.handle}__"]
        if options in (6, 7):
            return [objs.scene_index_path(obj, under_model=options == 7)]
        raise ApiError(f"sim.getObjectAlias: options must be -1..7, got {options}")

    def get_object_name(self, client: ClientState, handle: int) -> list[Any]:
        return [self._object(handle, "sim.getObjectName").name]

    def get_object_type(self, client: ClientState, handle: int) -> list[Any]:
        return [OBJECT_TYPES[self._object(handle, "sim.getObjectType").kind]]

    def get_object_parent(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getObjectParent")
        return [obj.parent if obj.parent is not None else -1]

    def get_object_child(self, client: ClientState, handle: int, index: int) -> list[Any]:
        obj = self._object(handle, "sim.getObjectChild")
        kids = self.objects.children(obj)
        return [kids[index].handle if 0 <= index < len(kids) else -1]

    def get_objects_in_tree(
        self, client: ClientState, base: int, object_type: int, options: int
    ) -> list[Any]:
        func = "sim.getObjectsInTree"
        root = None if base == HANDLE_SCENE else self._object(base, func)
        if options & 2:  # first children only
            found = self.objects.children(root)
        else:
            found = self.objects.tree(root)
            if options & 1 and root is not None:  # exclude the tree base
                found = found[1:]
        if object_type != HANDLE_ALL:
            found = [o for o in found if OBJECT_TYPES[o.kind] == object_type]
        return [[o.handle for o in found]]

    def get_objects(self, client: ClientState, index: int, object_type: int) -> list[Any]:
        found = [o for o in self.objects if object_type in (HANDLE_ALL, OBJECT_TYPES[o.kind])]
        return [found[index].handle if 0 <= index < len(found) else -1]

    def is_handle(self, client: ClientState, handle: int) -> list[Any]:
        return [self.objects.get(handle) is not None]

    def get_model_property(self, client: ClientState, handle: int) -> list[Any]:
        obj = self._object(handle, "sim.getModelProperty")
        return [0 if obj.model else _C["modelproperty_not_model"]]

    def get_object_size_factor(self, client: ClientState, handle: int) -> list[Any]:
        self._object(handle, "sim.getObjectSizeFactor")
        return [1.0]  # served models are never scaled
