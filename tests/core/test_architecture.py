"""The dependency rules of ARCHITECTURE.md, checked on the source, and a light import."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

import puckboard

PKG = Path(puckboard.__file__).parent


def imported_puckboard_modules(path: Path) -> set[str]:
    """Absolute names of the puckboard modules a file imports (relative imports resolved)."""
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
                out.add(name)
                out.update(f"{name}.{a.name}" for a in node.names)
    return out


def files_of(subpackage: str) -> list[Path]:
    root = PKG / subpackage
    return sorted(root.rglob("*.py")) if root.is_dir() else [PKG / f"{subpackage}.py"]


@pytest.mark.parametrize(
    ("subpackage", "forbidden"),
    [
        ("blackboard", ("puckboard.",)),  # imports nothing else of puckboard
        ("behaviours", ("puckboard.adapters", "puckboard.sim", "puckboard.cli")),
        (
            "sim",
            (
                "puckboard.behaviours",
                "puckboard.control",
                "puckboard.cli",
                "puckboard.adapters",
                "puckboard.remote",
                "puckboard.emulator",
            ),
        ),
        (
            "scenario",
            (
                "puckboard.sim",
                "puckboard.adapters",
                "puckboard.remote",
                "puckboard.emulator",
                "puckboard.behaviours",
                "puckboard.control",
                "puckboard.cli",
            ),
        ),
        ("adapters", ("puckboard.cli", "puckboard.behaviours")),
        ("control", ("puckboard.cli",)),
        ("records", ("puckboard.cli", "puckboard.adapters", "puckboard.sim")),
    ],
)
def test_dependencies_point_one_way(subpackage, forbidden):
    offenders = []
    for path in files_of(subpackage):
        for name in imported_puckboard_modules(path):
            if subpackage == "blackboard" and name.startswith("puckboard.blackboard"):
                continue
            if any(
                name == f.rstrip(".")
                or name.startswith(f.rstrip(".") + ".")
                or (f.endswith(".") and name.startswith(f))
                for f in forbidden
            ):
                offenders.append(f"{path.relative_to(PKG.parent)} imports {name}")
    assert offenders == []


@pytest.mark.parametrize(
    "subpackage", ["adapters", "remote", "emulator", "control", "viz", "sweep", "web"]
)
def test_backends_use_the_engine_only_through_its_world(subpackage):
    """Outside the engine, only ``World`` is imported: the rest of sim/ is its internals."""
    allowed = {"puckboard.sim.world", "puckboard.sim.world.World"}
    offenders = [
        f"{p.relative_to(PKG.parent)} imports {n}"
        for p in files_of(subpackage)
        for n in imported_puckboard_modules(p)
        if (n == "puckboard.sim" or n.startswith("puckboard.sim.")) and n not in allowed
    ]
    assert offenders == []


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
        "heavy = ['numpy', 'py_trees', 'matplotlib', 'zmq', 'serial', 'rich', 'dask', 'filterpy', 'aiohttp']\n"
        "print(','.join(m for m in heavy if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


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
