"""The experiments' figures module: one palette, one type size, and figures that leave
the caller's matplotlib backend alone."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import puckboard
from puckboard.viz import figures, style

PKG = Path(puckboard.__file__).parent


def test_no_library_module_switches_the_backend_or_imports_pyplot_to_draw_a_file():
    """``matplotlib.use`` belongs to whoever runs the program (a notebook has its own);
    pyplot only where a window is the point (the live view)."""
    offenders = []
    for path in PKG.rglob("*.py"):
        rel = path.relative_to(PKG)
        if rel.parts[0] == "cli":
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            use = isinstance(node, ast.Attribute) and node.attr == "use"
            if use and getattr(node.value, "id", None) == "matplotlib":  # type: ignore[attr-defined]
                offenders.append(f"{rel}:{node.lineno} matplotlib.use")
            pyplot = isinstance(node, ast.Import) and any(
                a.name == "matplotlib.pyplot" for a in node.names
            )
            if pyplot and rel.as_posix() != "viz/live.py":
                offenders.append(f"{rel}:{node.lineno} imports pyplot")
    assert offenders == []


def test_the_palette_is_written_once_and_the_figures_take_theirs_from_it():
    assert set(figures.COLOURS) <= set(figures.OKABE_ITO.values())
    assert len(set(figures.COLOURS)) == len(figures.COLOURS)
    assert figures.OKABE_ITO["yellow"] not in figures.COLOURS  # does not show on white
    written = []
    for folder in ("sensitivity", "sweep", "tune", "bench"):
        written += [p for p in (PKG / folder).rglob("*.py") if _hex_of_the_palette(p)]
    written += [p for p in (PKG / "viz" / "style.py",) if _hex_of_the_palette(p)]
    assert written == []
    assert style.__dict__["_BLUE"] == figures.OKABE_ITO["blue"]


def _hex_of_the_palette(path: Path) -> bool:
    """Whether the code of ``path`` spells a colour of the palette (black aside)."""
    palette = {c for c in figures.OKABE_ITO.values() if c != "#000000"}
    return any(
        isinstance(node, ast.Constant) and str(node.value).upper() in palette
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
    )


def test_a_figure_is_drawn_without_touching_the_backend(tmp_path):
    matplotlib = pytest.importorskip("matplotlib")
    before = matplotlib.rcParams["backend"]
    fig = figures.new_figure(figsize=(2, 1))
    fig.subplots().plot([0, 1], [0, 1])
    fig.savefig(tmp_path / "f.png")
    assert (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"
    assert matplotlib.rcParams["backend"] == before
