import io

import pydot
import pytest
from PIL import Image

from puckboard.behaviours import improved, stock
from puckboard.cli import main
from puckboard.viz import tree as tree_mod
from puckboard.viz.tree import GraphvizMissingError, render_tree


def _names(controller):
    return [node.name for node in controller.root.iterate()]


@pytest.mark.parametrize("fmt", ["ascii", "unicode"])
@pytest.mark.parametrize("factory", [stock, improved])
def test_text_trees_name_every_node(fmt, factory):
    controller = factory()
    text = render_tree(controller, fmt)
    for name in _names(controller):
        assert name in text
    # priority order is top to bottom
    layers = [c.name for c in controller.root.children]
    assert [text.index(n) for n in layers] == sorted(text.index(n) for n in layers)


def test_text_trees_give_priority_and_keys_and_the_two_styles_differ():
    """What --help promises: priority order (1 = highest) and the keys each layer reads."""
    controller = improved()
    text = render_tree(controller, "unicode")
    for rank, layer in enumerate(controller.root.children, start=1):
        line = next(row for row in text.splitlines() if f"{rank}. {layer.name}" in row)
        for key in getattr(layer, "reads", ()):
            assert key in line.split("reads:")[1], (layer.name, line)
    ascii_text = render_tree(controller, "ascii")
    assert "└── 4. Cruise" in text and "`-- 4. Cruise" in ascii_text
    assert ascii_text.isascii() and not text.isascii()


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_dot_parses_and_has_every_node_and_edge():
    controller = improved()
    graphs = pydot.graph_from_dot_data(render_tree(controller, "dot"))
    assert graphs is not None and len(graphs) == 1
    graph = graphs[0]
    nodes = {n.get_name().strip('"') for n in graph.get_nodes()} - {"node", "graph", "edge"}
    assert nodes == set(_names(controller))
    assert len(graph.get_edges()) == len(controller.root.children)
    label = graph.get_node("LineFollow")[0].get("label")
    assert "2. LineFollow" in label and "ground" in label


def test_png_and_svg_through_graphviz(tmp_path):
    if tree_mod.dot_executable() is None:
        pytest.skip("Graphviz 'dot' is not installed")
    png = render_tree(improved(), "png")
    with Image.open(io.BytesIO(png)) as im:
        assert im.format == "PNG" and im.size[0] > 200
    svg = render_tree(improved(), "svg")
    assert "<svg" in svg and "FrontObstacleLeftTurn" in svg


def test_missing_graphviz_is_explained(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(tree_mod, "dot_executable", lambda: None)
    with pytest.raises(GraphvizMissingError, match="graphviz"):
        render_tree(improved(), "svg")
    assert main(["tree", "-o", str(tmp_path / "t.png")]) == 2
    assert "install graphviz" in capsys.readouterr().err


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_cli_writes_dot_to_a_file_and_text_to_stdout(tmp_path, capsys):
    assert main(["tree", "--controller", "stock"]) == 0
    out = capsys.readouterr().out
    assert "FrontBraitenbergAvoid" in out
    target = tmp_path / "tree.dot"
    assert main(["tree", "-o", str(target)]) == 0
    assert pydot.graph_from_dot_data(target.read_text())
    assert main(["tree", "--controller", "nonsense"]) == 2


def test_the_tree_shown_in_the_docs_is_what_puckboard_tree_prints():
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "visual-tools.md").read_text(
        encoding="utf-8"
    )
    assert render_tree(improved(), "unicode") in doc


def test_the_status_markers_the_tutorial_explains_are_py_trees_own():
    """docs/tutorial.md explains [o], -->, [-], [*] and [x]: they must be what prints."""
    from puckboard.backends import FakeAdapter

    controller = improved()
    fresh = controller.ascii_tree()
    assert fresh.startswith("[o] improved [-]") and "--> Cruise [-]" in fresh
    robot = FakeAdapter()
    robot.sense_all()
    controller.tick(robot.ns)
    ticked = controller.ascii_tree()
    assert "--> Cruise [*]" in ticked and "--> LineFollow [x]" in ticked
