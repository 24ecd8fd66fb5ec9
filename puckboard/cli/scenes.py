"""``puckboard scenes``: list the shipped scenes, or print one to start your own from."""

from __future__ import annotations

import argparse

from .common import CliError


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
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    from ..errors import SceneError
    from ..scenario.scenefile import load_scene, scene_names, scene_path

    if args.action == "show":
        if not args.name:
            raise CliError(f"which scene? puckboard scenes show NAME ({', '.join(scene_names())})")
        try:
            text = scene_path(args.name).read_text(encoding="utf-8")
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
            f"{name:<{width}}  {robots} robot{'s' if robots != 1 else ''}, goal {scene.goal.resolve(scene)}: {first}"
        )
    return 0
