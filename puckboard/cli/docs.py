"""``puckboard docs``: build the documentation site locally, or serve it with live reload.

The docs are a MkDocs site (``mkdocs.yml`` at the root of a puckboard source checkout)
whose API reference is generated from the package's docstrings by mkdocstrings, so the
reference always matches the code you have installed. Building needs the ``docs`` extra:
``pip install 'puckboard[docs]'``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from .checks import check_port, check_writable
from .errors import CliError

#: Python modules the build needs, with the distribution that provides each.
REQUIRED_MODULES: dict[str, str] = {
    "mkdocs": "mkdocs",
    "material": "mkdocs-material",
    "mkdocstrings": "mkdocstrings",
    "mkdocstrings_handlers.python": "mkdocstrings-python",
}


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "docs",
        help="build the documentation (tutorial, layers, API reference) or serve it",
        description=(
            "Build the documentation site with MkDocs into a folder and print the page to "
            "open, or serve it on 127.0.0.1 with live reload. Needs the docs extra: "
            "pip install 'puckboard[docs]'."
        ),
    )
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        default=None,
        help="folder to build into (default: site/ next to mkdocs.yml)",
    )
    parser.add_argument(
        "--serve",
        action="store_true",
        help="run 'mkdocs serve' instead of building (rebuilds when a page changes)",
    )
    parser.add_argument("--port", type=int, default=8000, help="port for --serve (default: 8000)")
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="address for --serve (default: 127.0.0.1, this machine only)",
    )
    parser.add_argument(
        "--config",
        type=Path,
        default=None,
        help="mkdocs.yml to use (default: found from the current folder or the package)",
    )
    parser.add_argument(
        "--strict",
        action="store_true",
        help="treat warnings (broken links, bad docstrings) as errors",
    )
    parser.set_defaults(func=main)


def missing_modules() -> list[str]:
    """Distributions of the ``docs`` extra that are not importable, in a stable order."""
    import importlib.util

    missing = []
    for module, dist in REQUIRED_MODULES.items():
        try:
            found = importlib.util.find_spec(module) is not None
        except ModuleNotFoundError:  # the parent package of a dotted name is missing
            found = False
        if not found:
            missing.append(dist)
    return missing


def find_config(start: Path | None = None) -> Path | None:
    """``mkdocs.yml`` in ``start`` (default: the current folder) or a parent of it, else the
    one beside the installed package (an editable install of a source checkout)."""
    here = (start or Path.cwd()).resolve()
    for folder in (here, *here.parents):
        candidate = folder / "mkdocs.yml"
        if candidate.is_file() and (folder / "docs").is_dir():
            return candidate
    package_root = Path(__file__).resolve().parents[2]
    candidate = package_root / "mkdocs.yml"
    return candidate if candidate.is_file() else None


def main(args: argparse.Namespace) -> int:
    import os
    import subprocess
    import sys

    if args.serve:
        check_port(args.port, listen_on=args.host)
    elif args.output is not None:
        check_writable(args.output, "--output", folder=True)
    missing = missing_modules()
    if missing:
        raise CliError(
            f"building the docs needs {', '.join(missing)}; install them with: "
            "pip install 'puckboard[docs]'"
        )
    config = args.config if args.config is not None else find_config()
    if config is None or not Path(config).is_file():
        where = f"{args.config}" if args.config is not None else "this folder or its parents"
        raise CliError(
            f"no mkdocs.yml found in {where}; run this from a puckboard source checkout "
            "(git clone ...) or pass --config path/to/mkdocs.yml"
        )
    config = Path(config).resolve()
    env = dict(os.environ)
    env.setdefault("NO_MKDOCS_2_WARNING", "1")  # a theme banner that is noise for readers
    command = [sys.executable, "-m", "mkdocs"]
    if args.serve:
        command += ["serve", "-f", str(config), "-a", f"{args.host}:{args.port}"]
        if args.strict:
            command.append("--strict")
        print(f"serving the docs at http://{args.host}:{args.port}/ (Ctrl-C stops)", flush=True)
        return subprocess.call(command, cwd=config.parent, env=env)

    output = (args.output if args.output is not None else config.parent / "site").resolve()
    command += ["build", "-f", str(config), "-d", str(output), "--quiet"]
    if args.strict:
        command.append("--strict")
    status = subprocess.call(command, cwd=config.parent, env=env)
    if status != 0:
        raise CliError(f"mkdocs build failed (exit status {status}); see the messages above")
    index = output / "index.html"
    print(f"docs built; open {index.as_uri()}")
    return 0
