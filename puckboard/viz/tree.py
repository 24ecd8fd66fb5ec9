"""Behaviour-tree diagrams of a controller: text for the terminal, Graphviz for documents.

A controller is a py_trees tree (a Selector without memory over the layers), so py_trees
draws it for documents (``dot``, its pydot export); the text forms (``ascii``/``unicode``)
are drawn here. Both add what a student needs to read the diagram: each layer's priority
(1 = highest) and the blackboard keys it reads. ``png``/``svg`` run Graphviz's ``dot``
program, a system package, not a Python one; when it is missing the error says how to
install it.
"""

from __future__ import annotations

import platform
import shutil
import subprocess
from typing import TYPE_CHECKING

from ..errors import PuckboardError

if TYPE_CHECKING:
    from py_trees.behaviour import Behaviour

    from ..behaviours.controller import Controller

__all__ = [
    "TREE_FORMATS",
    "GraphvizMissingError",
    "graphviz_install_hint",
    "render_tree",
    "tree_dot",
    "tree_text",
]

TREE_FORMATS = ("ascii", "unicode", "dot", "png", "svg")


class GraphvizMissingError(PuckboardError):
    """An image of the tree was asked for but Graphviz's ``dot`` program is not installed."""


def graphviz_install_hint() -> str:
    system = platform.system()
    if system == "Darwin":
        how = "brew install graphviz"
    elif system == "Windows":
        how = "winget install graphviz (or choco install graphviz), then reopen the terminal"
    else:
        how = "sudo apt install graphviz (Debian/Ubuntu) or sudo dnf install graphviz (Fedora)"
    return (
        f"PNG and SVG need Graphviz's 'dot' program, which is not on PATH: {how}. "
        "'--format dot' writes the graph source without it."
    )


#: Branch glyphs: (middle child, last child, continuing line, blank) per style.
_BRANCHES = {
    True: ("├── ", "└── ", "│   ", "    "),
    False: ("+-- ", "`-- ", "|   ", "    "),
}


def tree_text(controller: Controller, *, unicode: bool = False) -> str:
    """The tree as indented text: each layer's priority (1 = highest) and the keys it reads.

    py_trees' own text display shows the tree's shape but neither the priority order a
    student reads the arbitration by nor the blackboard keys, and its unicode and ascii
    forms look alike in many terminals; this drawing shows both, with box-drawing branches
    (``unicode``) or plain ``+--`` ones.
    """
    mid, last, line, blank = _BRANCHES[unicode]
    root = controller.root
    rows: list[tuple[str, str]] = []  # (branch and label, keys read), aligned below

    def walk(node: Behaviour, prefix: str, rank: int | None, is_last: bool) -> None:
        label = f"{rank}. {node.name}" if rank is not None else node.name
        reads = tuple(getattr(node, "reads", ()))
        rows.append((f"{prefix}{last if is_last else mid}{label}", ", ".join(reads)))
        children = list(getattr(node, "children", ()))
        inner = prefix + (blank if is_last else line)
        for k, child in enumerate(children):
            walk(child, inner, None, k == len(children) - 1)

    children = list(root.children)
    for k, child in enumerate(children, start=1):
        walk(child, "", k, k == len(children))
    width = max((len(left) for left, _ in rows), default=0)
    lines = [f"{root.name}  (priority selector: the first layer that applies drives)"]
    lines += [f"{left:<{width}}   reads: {keys}" if keys else left for left, keys in rows]
    return "\n".join(lines)


def tree_dot(controller: Controller) -> str:
    """The tree as Graphviz dot source, layers labelled with priority and keys read."""
    import py_trees

    graph = py_trees.display.dot_tree(controller.root)
    from .style import layer_colours, text_colour

    colours = layer_colours([layer.name for layer in controller.every_layer])
    graph.set_name("controller")
    priority = {child.name: k for k, child in enumerate(controller.root.children, start=1)}
    by_name = {node.name: node for node in controller.root.iterate()}
    for node in graph.get_nodes():
        name = node.get_name().strip('"')
        behaviour = by_name.get(name)
        if behaviour is None:
            continue
        label = name
        if name in priority:
            label = f"{priority[name]}. {name}"
        reads = getattr(behaviour, "reads", ())
        if reads and behaviour is not controller.root:
            label += "\\nreads: " + ", ".join(reads)
        if behaviour is controller.root:
            label = f"{name}\\n(priority selector)"
            node.set("fillcolor", '"#e6e6e6"')
        node.set("label", f'"{label}"')
        node.set("fontsize", "14")
        node.set("fontname", "Helvetica")
        if not behaviour.children:  # a layer: its colour in every other view
            colour = colours.get(name, "#e6e6e6")
            node.set("fillcolor", f'"{colour}"')
            node.set("fontcolor", f'"{text_colour(colour)}"')
            node.set("shape", "box")
            node.set("style", '"filled,rounded"')
    return graph.to_string()  # type: ignore[no-any-return]


def dot_executable() -> str | None:
    return shutil.which("dot")


def render_tree(controller: Controller, fmt: str = "unicode") -> str | bytes:
    """The tree in ``fmt`` (see :data:`TREE_FORMATS`): text for ascii/unicode/dot/svg,
    bytes for png."""
    fmt = fmt.lower()
    if fmt not in TREE_FORMATS:
        raise ValueError(f"tree format must be one of {', '.join(TREE_FORMATS)}, got {fmt!r}")
    if fmt in ("ascii", "unicode"):
        return tree_text(controller, unicode=fmt == "unicode")
    source = tree_dot(controller)
    if fmt == "dot":
        return source
    exe = dot_executable()
    if exe is None:
        raise GraphvizMissingError(graphviz_install_hint())
    done = subprocess.run(
        [exe, f"-T{fmt}"], input=source.encode(), capture_output=True, check=False, timeout=60
    )
    if done.returncode != 0:
        raise PuckboardError(
            f"Graphviz 'dot' failed ({done.returncode}): {done.stderr.decode(errors='replace')}"
        )
    return done.stdout.decode() if fmt == "svg" else done.stdout
