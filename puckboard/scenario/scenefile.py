"""Scene files: the shipped scenes by name, and TOML or JSON files by path, read to a Scene.

A scene file is data a student edits by hand, so every mistake gets an error that names
the file, the field path and what was expected::

    my-scene.toml: robots[1].theta: expected a number (radians), got 'north'

This module finds the text (shipped scenes live in ``puckboard/scenario/scenes/`` and are
found by name: :func:`scene_names`, :func:`load_scene`) and parses it; the parsed dict
becomes a validated :class:`~puckboard.scenario.scene.Scene` in :mod:`.conversion`
(:func:`~.conversion.scene_from_dict`, and :func:`~.conversion.scene_to_dict` back).
Readability comes first: angles may be given in degrees, a track may be a parametric
shape (:mod:`.tracks`) and robots and obstacles may be placed on the track by a fraction
of the lap (:mod:`.placement`). The schema is documented in ``docs/scenarios.md``.
"""

from __future__ import annotations

import json
import sys
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import SceneError
from .conversion import scene_from_dict
from .scene import Scene

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib

__all__ = ["load_scene", "parse_scene_text", "scene_description", "scene_names", "scene_path"]

SCENE_SUFFIXES = (".toml", ".json")


def _scenes_dir() -> Any:
    return resources.files("puckboard.scenario").joinpath("scenes")


def scene_names() -> list[str]:
    """Names of the shipped scenes, sorted."""
    names = [
        entry.name.rsplit(".", 1)[0]
        for entry in _scenes_dir().iterdir()
        if entry.name.endswith(SCENE_SUFFIXES)
    ]
    return sorted(names)


def scene_path(name: str) -> Any:
    """The shipped file behind scene ``name`` (a ``Traversable``); ``SceneError`` if none."""
    folder = _scenes_dir()
    for suffix in SCENE_SUFFIXES:
        candidate = folder.joinpath(name + suffix)
        if candidate.is_file():
            return candidate
    raise SceneError(
        f"unknown scene {name!r}; shipped scenes: {', '.join(scene_names())} "
        "(or give the path of a .toml or .json scene file)"
    )


def load_scene(name_or_path: str | Path) -> Scene:
    """Load a shipped scene by name, or a scene file by path (``.toml`` or ``.json``)."""
    text = str(name_or_path)
    looks_like_path = isinstance(name_or_path, Path) or text.endswith(SCENE_SUFFIXES)
    looks_like_path = looks_like_path or "/" in text or "\\" in text
    if not looks_like_path:
        entry = scene_path(text)
        return parse_scene_text(entry.read_text(encoding="utf-8"), source=entry.name)
    path = Path(name_or_path)
    if path.suffix.lower() not in SCENE_SUFFIXES:
        raise SceneError(f"{path}: scene files must end in .toml or .json")
    try:
        content = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(f"cannot read scene file {str(path)!r}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise SceneError(f"{path}: scene files must be UTF-8 text") from None
    return parse_scene_text(content, source=str(path), default_name=path.stem)


def parse_scene_text(text: str, *, source: str, default_name: str | None = None) -> Scene:
    """Parse TOML or JSON text (chosen by ``source``'s suffix) into a validated scene."""
    if source.lower().endswith(".json"):
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise SceneError(f"{source}: not valid JSON: {exc}") from None
    else:
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise SceneError(f"{source}: not valid TOML: {exc}") from None
    if default_name is None:
        default_name = Path(source).name.rsplit(".", 1)[0]
    return scene_from_dict(data, source=source, default_name=default_name)


def scene_description(name: str) -> str:
    """The one-line description of a shipped scene (without building the world)."""
    return load_scene(name).description.strip().splitlines()[0] if name else ""
