"""The dependency rules of ARCHITECTURE.md, read from its tables and checked on the source,
and a light import."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

import puckboard

PKG = Path(puckboard.__file__).parent


def imported_puckboard_modules(path: Path) -> set[str]:
    """Absolute names of the puckboard modules a file imports (relative imports resolved).

    ``from pkg import name`` gives ``pkg.name``, and ``pkg`` too unless ``pkg.name`` is a
    module of its own (then the package's ``__init__`` is only passed through)."""
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    package = parts[:-1]  # the package a module (or __init__) lives in
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.startswith("puckboard"))
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            if name.startswith("puckboard"):
                subs = {f"{name}.{a.name}" for a in node.names}
                out.update(subs)
                if not all(_is_module(s) for s in subs):
                    out.add(name)
    return out


def _is_module(name: str) -> bool:
    rel = Path(*name.split(".")[1:])
    return (PKG / rel).with_suffix(".py").is_file() or (PKG / rel / "__init__.py").is_file()


def files_of(subpackage: str) -> list[Path]:
    root = PKG / subpackage
    return sorted(root.rglob("*.py")) if root.is_dir() else [PKG / f"{subpackage}.py"]


ARCHITECTURE = PKG.parent / "ARCHITECTURE.md"


def _table(header: str) -> list[list[str]]:
    """The rows of ARCHITECTURE.md's table whose header row starts ``| header |``, each
    as its cells (the separator row left out)."""
    lines = ARCHITECTURE.read_text(encoding="utf-8").splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"| {header} |"))
    rows = []
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
    return rows


def _parts(cell: str) -> list[str]:
    """The package parts a cell names in backticks (``examples/``, no part, left out)."""
    return [name for name in re.findall(r"`([^`]+)`", cell) if "/" not in name]


#: ARCHITECTURE.md's floors, lowest first: a module imports from its own floor or below.
FLOORS = tuple(tuple(_parts(row[2])) for row in _table("floor"))
#: ARCHITECTURE.md's parts that never import some parts below their floor (``*``: any).
NEVER = {
    part: tuple(_parts(row[1])) for row in _table("module") for part in _parts(row[0])
}


def _all_parts() -> set[str]:
    parts = {p.name.removesuffix(".py") for p in PKG.iterdir() if not p.name.startswith(".")}
    return parts - {"__init__", "__main__", "__pycache__", "py.typed"}


def test_architecture_md_gives_every_part_of_the_package_its_floor():
    named = [part for floor in FLOORS for part in floor]
    assert len(FLOORS) >= 9 and len(named) == len(set(named))  # the table was read
    assert sorted(_all_parts() - set(named)) == []  # a new part gets its floor there
    assert sorted(set(named) - _all_parts()) == []  # and a part gone leaves it
    assert set(NEVER) <= set(named) and "web" in NEVER and NEVER["blackboard"] == ("*",)
    for part, never in NEVER.items():
        assert set(never) - {"*"} <= set(named), part


@pytest.mark.parametrize("subpackage", sorted(NEVER))
def test_a_part_never_imports_what_architecture_md_says_it_never_does(subpackage):
    never = NEVER[subpackage]
    offenders = []
    for path in files_of(subpackage):
        for name in imported_puckboard_modules(path):
            target = name.split(".")[1] if name.count(".") else name
            if target == subpackage or target == "puckboard":
                continue
            if "*" in never or target in never:
                offenders.append(f"{path.relative_to(PKG.parent)} imports {name}")
    assert offenders == []


def test_outside_the_engine_only_its_world_is_imported():
    """The rest of sim/ is the engine's internals (the benchmarks time them, aside); its
    registry of IR sensor models is asked what a model is."""
    allowed = {"puckboard.sim.world", "puckboard.sim.world.World", "puckboard.sim.ir_models"}
    allowed |= {f"puckboard.sim.ir_models.{name}" for name in ("ir_model", "ir_model_names")}
    offenders = [
        f"{p.relative_to(PKG.parent)} imports {n}"
        for part in sorted(_all_parts() - {"sim", "bench"})
        for p in files_of(part)
        for n in imported_puckboard_modules(p)
        if (n == "puckboard.sim" or n.startswith("puckboard.sim.")) and n not in allowed
    ]
    assert offenders == []


def _module_name(path: Path) -> str:
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _import_graph() -> dict[str, set[str]]:
    """Module → the puckboard modules it imports (any import: top, function or TYPE_CHECKING).

    ``from pkg import name`` counts as importing ``pkg.name`` when that is a module, else
    ``pkg``. A package's ``__init__`` re-exporting its own submodules is left out: that
    is how a package presents itself, not a dependency running back up.
    """
    modules = {_module_name(p): p for p in PKG.rglob("*.py")}
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        targets = set()
        for imported in imported_puckboard_modules(path):
            while imported and imported not in modules:
                imported = imported.rpartition(".")[0]
            if imported and imported != name:
                targets.add(imported)
        if path.name == "__init__.py":
            targets = {t for t in targets if not t.startswith(name + ".")}
        graph[name] = targets
    return graph


def test_the_import_graph_has_no_circle():
    graph = _import_graph()
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    sys.setrecursionlimit(10_000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    assert circles == []


def test_no_part_of_the_package_imports_one_above_its_floor():
    floor_of = {part: n for n, parts in enumerate(FLOORS) for part in parts}
    upward = []
    for path in PKG.rglob("*.py"):
        part = path.relative_to(PKG).parts[0].removesuffix(".py")
        if part in ("__init__", "__main__"):
            continue
        for name in imported_puckboard_modules(path):
            target = name.split(".")[1] if name.count(".") else None
            if target in floor_of and floor_of[target] > floor_of[part]:
                upward.append(f"{path.relative_to(PKG.parent)} imports {name}")
    assert upward == []


def test_no_module_imports_its_own_package_init():
    """A module that imports the ``__init__`` of a package it lives in runs back up."""
    offenders = []
    for path in PKG.rglob("*.py"):
        if path.name == "__init__.py":
            continue
        name = _module_name(path)
        packages = {name.rsplit(".", k)[0] for k in range(1, name.count(".") + 1)}
        for imported in imported_puckboard_modules(path):
            if imported in packages and imported != "puckboard":
                offenders.append(f"{path.relative_to(PKG.parent)} imports {imported}")
    assert offenders == []


def test_no_file_of_the_package_is_over_about_600_lines():
    lengths = {
        str(p.relative_to(PKG.parent)): len(p.read_text(encoding="utf-8").splitlines())
        for p in PKG.rglob("*.py")
    }
    assert {name: n for name, n in lengths.items() if n > 650} == {}


def test_no_core_module_imports_the_cli():
    offenders = [
        f"{p.relative_to(PKG.parent)} imports {n}"
        for p in PKG.rglob("*.py")
        if "cli" not in p.relative_to(PKG).parts and p.name != "__main__.py"
        for n in imported_puckboard_modules(p)
        if n.startswith("puckboard.cli")
    ]
    assert offenders == []


def test_import_puckboard_loads_no_heavy_or_optional_package():
    code = (
        "import sys, puckboard\n"
        "heavy = ['numpy', 'py_trees', 'matplotlib', 'zmq', 'serial', 'rich', 'dask', "
        "'filterpy', 'aiohttp']\n"
        "print(','.join(m for m in heavy if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


TEACHING = [
    "Layer",
    "Controller",
    "Frame",
    "WheelCommand",
    "Cruise",
    "LineFollow",
    "FrontObstacleLeftTurn",
    "SideWallKeep",
    "run_episode",
]


def test_a_first_layer_imports_everything_from_puckboard_and_only_then_loads_it():
    """The tutorial's one import line: each name the object of its own module, loaded on
    first use (``import puckboard`` alone stays light, above)."""
    from puckboard import behaviours, records
    from puckboard.control import episode

    homes = {"WheelCommand": records, "run_episode": episode}
    for name in TEACHING:
        assert getattr(puckboard, name) is getattr(homes.get(name, behaviours), name), name
        assert name in puckboard.__all__ and name in dir(puckboard)


def test_library_code_never_prints():
    offenders = []
    for p in PKG.rglob("*.py"):
        if "cli" in p.relative_to(PKG).parts or p.name == "__main__.py":
            continue
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "print":
                offenders.append(f"{p.relative_to(PKG.parent)}:{node.lineno}")
    assert offenders == []


def test_package_is_typed():
    assert (PKG / "py.typed").is_file()
