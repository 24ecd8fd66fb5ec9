"""``puckboard examples``: list the installed teaching examples, show or run one.

The examples ship inside the package (``puckboard.examples``), so they are reachable after
a plain install, without a clone of the repository.
"""

from __future__ import annotations

import argparse

from .errors import CliError, user_code_error


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "examples",
        help="list the teaching examples, show one or run it ('examples run NAME')",
        description=(
            "List the examples installed with puckboard, print one's source to copy and "
            "edit ('puckboard examples show first_layer > my_layer.py'), or run one "
            "('puckboard examples run go_home --duration 60'); arguments after NAME "
            "go to the example (those that take any: see 'examples run NAME --help')."
        ),
    )
    parser.add_argument("action", nargs="?", choices=("list", "show", "run"), default="list")
    parser.add_argument("name", nargs="?", help="example to show or run")
    parser.add_argument(
        "example_args", nargs=argparse.REMAINDER, help="arguments passed to the example"
    )
    parser.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    import runpy
    import sys

    names = example_names()
    if args.action == "list":
        if args.name:
            raise CliError("'puckboard examples' takes no name; use 'examples show NAME' or 'run'")
        width = max(len(n) for n in names)
        for name in names:
            print(f"{name:<{width}}  {summary(name)}")
        return 0
    if not args.name:
        raise CliError(f"which example? puckboard examples {args.action} NAME ({', '.join(names)})")
    name = args.name.removesuffix(".py")
    if name not in names:
        raise CliError(f"no example {args.name!r}; examples: {', '.join(names)}")
    if args.example_args and args.action != "run":
        raise CliError(
            f"'examples {args.action}' takes only a NAME, got {' '.join(args.example_args)!r}"
        )
    if args.example_args and not takes_arguments(name):
        takers = [n for n in names if takes_arguments(n)]
        raise CliError(
            f"example {name!r} takes no arguments, got "
            f"{' '.join(args.example_args)!r}; examples that take some: "
            f"{', '.join(takers) or 'none'} ('puckboard examples run NAME --help')"
        )
    if args.action == "show":
        print(_source(name), end="")
        return 0
    saved = sys.argv
    sys.argv = [f"puckboard examples run {name}", *args.example_args]
    try:
        runpy.run_module(f"puckboard.examples.{name}", run_name="__main__", alter_sys=True)
    except SystemExit as exc:  # an example's own argparse error or exit status
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except Exception as exc:
        # an example edited in place (an editable install) fails as 'python example.py'
        # would show it, without the frames of this command and of runpy
        shown = user_code_error(exc, f"the example {name!r}", runpy.run_module)
        if shown is None:
            raise
        raise shown from None
    finally:
        sys.argv = saved
    return 0


def example_names() -> list[str]:
    """The installed examples' module names, sorted."""
    import importlib.resources

    folder = importlib.resources.files("puckboard.examples")
    return sorted(
        entry.name.removesuffix(".py")
        for entry in folder.iterdir()
        if entry.name.endswith(".py") and not entry.name.startswith("_")
    )


def takes_arguments(name: str) -> bool:
    """Whether example ``name`` reads its command line (argparse or ``sys.argv``): the
    others would run as if an argument given to them were not there."""
    import ast

    for node in ast.walk(ast.parse(_source(name))):
        if isinstance(node, ast.Import) and any(a.name == "argparse" for a in node.names):
            return True
        if isinstance(node, ast.ImportFrom) and node.module == "argparse":
            return True
        if isinstance(node, ast.Attribute) and node.attr == "argv":
            return True
    return False


def summary(name: str) -> str:
    """The first line of an example's docstring, read without running the example."""
    import ast

    doc = ast.get_docstring(ast.parse(_source(name))) or ""
    return doc.splitlines()[0] if doc else ""


def _source(name: str) -> str:
    """The text of installed example ``name`` (a zip or a folder, wherever it was put)."""
    import importlib.resources

    path = importlib.resources.files("puckboard.examples").joinpath(f"{name}.py")
    return path.read_text(encoding="utf-8")
