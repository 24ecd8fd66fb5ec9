"""``puckboard scenes``: list the shipped scenes, or print one to start your own from."""

from __future__ import annotations

import argparse

from .checks import seed_type
from .errors import CliError


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "scenes",
        help="list the shipped scenes, or print one ('scenes show NAME')",
        description=(
            "List the scenes shipped with puckboard with their descriptions, or print a "
            "scene file ('puckboard scenes show two-robot-pass > my-scene.toml') to edit "
            "and run with 'puckboard run my-scene.toml'."
        ),
    )
    parser.add_argument("action", nargs="?", choices=("list", "show"), default="list")
    parser.add_argument("name", nargs="?", help="scene to print (with 'show')")
    parser.add_argument(
        "--seed", type=seed_type, default=None,
        help="with 'show' and a generated scene (generated-pass): print the scene that "
        "seed draws, as a file 'puckboard run' runs to the same result as "
        "'puckboard run NAME --seed N'",
    )  # fmt: skip
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..errors import SceneError
    from ..scenario.scenefile import load_scene, scene_names

    if args.action == "show":
        if not args.name:
            raise CliError(f"which scene? puckboard scenes show NAME ({', '.join(scene_names())})")
        try:
            text = _scene_text(args.name) if args.seed is None else _seed_text(args.name, args.seed)
        except SceneError as exc:
            raise CliError(str(exc)) from None
        print(text, end="" if text.endswith("\n") else "\n")
        return 0
    if args.name:
        raise CliError(
            "'puckboard scenes' takes no name; did you mean 'puckboard scenes show NAME'?"
        )
    names = scene_names()
    width = max(len(n) for n in names)
    for name in names:
        scene = load_scene(name)
        first = " ".join(scene.description.split())
        robots = len(scene.robots)
        print(
            f"{name:<{width}}  {robots} robot{'s' if robots != 1 else ''}, "
            f"goal {scene.goal.resolve(scene)}: {first}"
        )
    return 0


def _seed_text(name: str, seed: int) -> str:
    """The scene generated scene ``name`` draws for ``seed``, as a TOML scene file."""
    from ..errors import SceneError
    from ..scenario.conversion import for_seed, scene_to_dict
    from ..scenario.scene_toml import scene_toml
    from ..scenario.scenefile import load_scene

    scene = load_scene(name)
    if scene.generate is None:
        raise SceneError(
            f"scene {scene.name!r} is not generated, so --seed draws nothing in it; "
            f"print it with 'puckboard scenes show {name}'"
        )
    header = (
        f"Scene {scene.name!r} as seed {seed} draws it (puckboard scenes show {name} "
        f"--seed {seed}).\nRun it with: puckboard run THIS-FILE.toml --seed {seed} "
        "(the same run as\n"
        f"puckboard run {name} --seed {seed}; another --seed keeps this track)."
    )
    return scene_toml(scene_to_dict(for_seed(scene, seed)), header)


def _scene_text(name: str) -> str:
    """The text of shipped scene ``name``, or of the scene file at ``name`` (checked by
    loading it first, so that 'show' says what 'run' would say of a broken file): the
    refusal of an unknown name suggests giving a file, so a file is accepted."""
    from pathlib import Path

    from ..errors import SceneError
    from ..scenario.scenefile import load_scene, scene_path

    try:
        return str(scene_path(name).read_text(encoding="utf-8"))
    except SceneError:
        if not Path(name).is_file():
            raise
    load_scene(name)
    return Path(name).read_text(encoding="utf-8")
