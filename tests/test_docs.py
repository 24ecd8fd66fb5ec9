"""The documentation works: the tutorial's code runs, the site builds without warnings,
every page is reachable, and ``puckboard docs`` builds it.

A newcomer follows the tutorial literally, so its code blocks are executed in order, in
one fresh interpreter, exactly as written (headless: matplotlib on the Agg backend).
"""

from __future__ import annotations

import importlib.util
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import doc_pages
import pytest
from cli_runs import run_in

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
MKDOCS_YML = ROOT / "mkdocs.yml"

HAVE_MKDOCS = all(
    importlib.util.find_spec(m) is not None for m in ("mkdocs", "material", "mkdocstrings")
)
needs_mkdocs = pytest.mark.skipif(
    not HAVE_MKDOCS, reason="mkdocs is not installed (pip install 'puckboard[docs]')"
)


def headless_env() -> dict[str, str]:
    env = dict(os.environ)
    env["MPLBACKEND"] = "Agg"
    env["NO_MKDOCS_2_WARNING"] = "1"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    return env


def nav_pages() -> list[str]:
    """Every page named in mkdocs.yml's nav (a tiny YAML reader: nav entries end in .md)."""
    text = MKDOCS_YML.read_text(encoding="utf-8")
    nav = text[text.index("\nnav:") :]
    return re.findall(r":\s*([\w./-]+\.md)\s*$", nav, flags=re.MULTILINE)


# -- the tutorial -------------------------------------------------------------------------
def fenced(page: Path, language: str) -> list[str]:
    pattern = re.compile(rf"^```{language}[^\n]*\n(.*?)^```", re.MULTILINE | re.DOTALL)
    return [m.group(1) for m in pattern.finditer(page.read_text(encoding="utf-8"))]


def shell_commands(page: Path) -> list[str]:
    """The ``puckboard ...`` lines of the page's bash blocks, in order.

    Installation lines (making and activating a virtual environment, ``pip install``)
    are the one thing not run: the test environment has puckboard installed already,
    and installing from the network is not a test.
    """
    setup = ("pip ", "python -m venv ", "source ")
    commands = []
    for block in fenced(page, "bash"):
        for line in block.splitlines():
            line = line.strip()
            if line.startswith("puckboard"):
                commands.append(line)
            else:
                assert not line or line.startswith(setup), f"unexpected shell line: {line}"
    return commands


def test_tutorial_has_code_to_run() -> None:
    page = DOCS / "tutorial.md"
    assert len(fenced(page, "python")) >= 6, "the tutorial should walk through runnable steps"
    assert any("--controller my_controller.py:my_controller" in c for c in shell_commands(page))


#: Printed between the tutorial's blocks, to cut the run's output into each block's part.
BLOCK_MARK = "@@ tutorial block {} @@"


@pytest.mark.slow
def test_tutorial_code_runs_in_order_and_prints_exactly_what_the_page_shows(
    tmp_path: Path,
) -> None:
    """The Python blocks, concatenated, run as one script (as a reader pasting them into
    one session would); a block that starts with ``# NAME.py`` is also saved as that file,
    as the reader is told to; then every ``puckboard`` command of the page runs.

    Each ``text`` block the page shows is exactly what the Python blocks since the previous
    one printed, numbers included: the seed is fixed, so a number that differs is a page
    that drifted. A block group that prints and shows nothing fails too."""
    page = DOCS / "tutorial.md"
    blocks = fenced(page, "python")
    for block in blocks:
        first = block.splitlines()[0].strip()
        if re.fullmatch(r"# [\w-]+\.py", first):
            (tmp_path / first[2:]).write_text(block, encoding="utf-8")
    script = tmp_path / "tutorial.py"
    script.write_text(
        "\n\n".join(f"print({BLOCK_MARK.format(i)!r})\n{b}" for i, b in enumerate(blocks)),
        encoding="utf-8",
    )
    result = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,  # a student's own folder, not the repository
        env=headless_env(),
        capture_output=True,
        text=True,
        timeout=300,
    )
    out = result.stdout
    assert result.returncode == 0, (
        f"a tutorial block failed:\n{out[-3000:]}\n{result.stderr[-3000:]}"
    )
    printed = re.split(r"^@@ tutorial block \d+ @@\n", out, flags=re.MULTILINE)[1:]
    assert len(printed) == len(blocks)

    # walk the page: python blocks print, the next text block shows what they printed
    since_shown: list[str] = []
    index = 0
    for language, body in doc_pages.fences(page.read_text(encoding="utf-8")):
        if language == "python":
            since_shown.append(printed[index])
            index += 1
        elif language == "text":
            doc_pages.assert_shown(
                body, "".join(since_shown), f"tutorial, the output after python block {index}"
            )
            since_shown = []
    assert not "".join(since_shown).strip(), (
        f"the last blocks print, the page shows nothing: {since_shown}"
    )
    # step 2: stock fails at the meeting; improved gets the robots past each other
    assert re.search(
        r"stock +the robots got past each other untouched: False +outcome: failed \(collision\)",
        out,
    )
    assert re.search(r"improved +the robots got past each other untouched: True ", out), out[-3000:]

    # what the prose around the outputs says of them
    # step 3: who drives when, read from the blackboard, in the order the page describes
    layers = re.findall(r"^t=.*->\s+(\w+)$", out, flags=re.MULTILINE)
    assert layers[:3] == ["LineFollow", "FrontObstacleLeftTurn", "SideWallKeep"], layers
    # step 7: the parameter change has a visible effect on a metric
    on_line = {
        float(m.group(1)): int(m.group(2))
        for m in re.finditer(r"inner_factor=([\d.]+): on the line (\d+)%", out)
    }
    assert set(on_line) == {0.25, 0.9}, out[-3000:]
    assert on_line[0.25] - on_line[0.9] >= 30, on_line

    for command in shell_commands(page):  # in this process, in the reader's folder
        status, printed = run_in(tmp_path, shlex.split(command)[1:])
        assert status == 0, f"{command}\n{printed[-2000:]}"


# -- the site -----------------------------------------------------------------------------
def test_every_nav_entry_exists_once_and_the_teaching_pages_are_listed() -> None:
    pages = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md")}
    listed = nav_pages()
    assert len(listed) == len(set(listed)), "a page is listed twice in the nav"
    missing = sorted(set(listed) - pages)
    assert not missing, f"nav names pages that do not exist: {missing}"
    teaching = {"index.md", "tutorial.md", "architectures.md", "lecturer-notes.md", "faq.md"}
    teaching |= {p for p in pages if p.startswith(("layers/", "api/"))}
    unlisted = sorted(teaching - set(listed))
    assert not unlisted, f"pages not reachable from the nav (add them to mkdocs.yml): {unlisted}"


def test_every_image_the_pages_show_exists() -> None:
    for page in DOCS.rglob("*.md"):
        for target in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", page.read_text(encoding="utf-8")):
            assert (page.parent / target).resolve().is_file(), f"{page.name} shows missing {target}"


@needs_mkdocs
@pytest.mark.slow
def test_docs_build_strict_clean_through_puckboard_docs(tmp_path: Path) -> None:
    """``puckboard docs --strict`` runs ``mkdocs build --strict`` (warnings are errors:
    broken links, missing images, unresolvable docstrings) and prints the page to open."""
    out = tmp_path / "site"
    result = subprocess.run(
        [sys.executable, "-m", "puckboard", "docs", "--strict", "--output", str(out)],
        cwd=ROOT, env=headless_env(), capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-4000:]
    assert (out / "index.html").is_file()
    assert (out / "index.html").as_uri() in result.stdout
    # the reference really was generated from docstrings, not left as ::: directives
    core = (out / "api" / "core.html").read_text(encoding="utf-8")
    assert "thread-safe key/value store" in core  # Blackboard's docstring
    behaviours = (out / "api" / "behaviours.html").read_text(encoding="utf-8")
    assert "Follow a dark line" in behaviours  # LineFollow's docstring
    for page in out.rglob("*.html"):
        html = page.read_text(encoding="utf-8")
        assert "::: puckboard" not in html, page
        assert not re.search(r":(class|func|meth|mod|attr):<code>", html), f"raw role in {page}"
    assert_local_links_open_pages(out)


def assert_local_links_open_pages(site: Path) -> None:
    """Opened from disk (file://), every local link must land on a file, not a folder:
    a directory URL shows a listing there, not the page."""
    broken = []
    for page in site.rglob("*.html"):
        if page.name == "404.html":
            continue  # a web server's error page, with site-absolute links by design
        html = page.read_text(encoding="utf-8")
        for href in re.findall(r'href="([^"#?]+)', html):
            if re.match(r"^[a-z][a-z0-9+.-]*:", href) or href.startswith("//"):
                continue  # external (https:, mailto:, data:)
            target = (page.parent / href).resolve()
            if not target.is_file():
                broken.append(f"{page.relative_to(site)} -> {href}")
    assert not broken, broken[:20]


# -- puckboard docs -----------------------------------------------------------------------
def test_puckboard_docs_names_the_missing_extra(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from puckboard.cli import docs as docs_cli
    from puckboard.cli import main

    real_find_spec = importlib.util.find_spec

    def no_mkdocs(name: str, *args: object, **kwargs: object):  # type: ignore[no-untyped-def]
        if name.split(".")[0] in ("mkdocs", "mkdocstrings"):
            return None
        return real_find_spec(name, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(importlib.util, "find_spec", no_mkdocs)
    assert "mkdocs" in docs_cli.missing_modules()
    assert main(["docs"]) == 2
    err = capsys.readouterr().err
    assert "pip install 'puckboard[docs]'" in err


def test_puckboard_docs_without_a_config_says_where_it_looked(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from puckboard.cli import main

    status = main(["docs", "--config", str(tmp_path / "nowhere" / "mkdocs.yml")])
    assert status == 2
    assert "no mkdocs.yml found" in capsys.readouterr().err


def test_find_config_walks_up_from_a_subfolder() -> None:
    from puckboard.cli.docs import find_config

    assert find_config(DOCS / "layers") == MKDOCS_YML


def test_puckboard_docs_serve_binds_this_machine_only_by_default(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from puckboard.cli import docs as docs_cli
    from puckboard.cli import main

    if docs_cli.missing_modules():
        pytest.skip("mkdocs is not installed (pip install 'puckboard[docs]')")
    calls: list[list[str]] = []
    monkeypatch.setattr(subprocess, "call", lambda argv, **kw: calls.append(argv) or 0)
    assert main(["docs", "--serve", "--config", str(MKDOCS_YML)]) == 0
    (argv,) = calls
    assert argv[1:4] == ["-m", "mkdocs", "serve"]
    assert argv[argv.index("-a") + 1] == "127.0.0.1:8000"
    assert "http://127.0.0.1:8000/" in capsys.readouterr().out


LAYER_PAGES = {
    "layers/line-follow.md": ("LineFollow",),
    "layers/front-obstacle.md": ("FrontBraitenbergAvoid", "FrontObstacleLeftTurn"),
    "layers/side-wall-keep.md": ("SideWallKeep",),
    "layers/clearance-guard.md": ("ClearanceGuard",),
    "layers/line-search.md": ("LineSearch",),
    "layers/cruise.md": ("Cruise",),
    "layers/hold-for.md": ("HoldFor",),
}


@pytest.mark.parametrize("page", sorted(LAYER_PAGES))
def test_layer_page_documents_exactly_the_layers_parameters(page: str) -> None:
    """A layer page's parameter table lists every constructor parameter and no other, so
    the page cannot drift from the code."""
    import inspect

    import puckboard.behaviours as behaviours

    expected: set[str] = set()
    for cls_name in LAYER_PAGES[page]:
        signature = inspect.signature(getattr(behaviours, cls_name).__init__)
        expected |= {p for p in signature.parameters if p not in ("self", "name")}
    text = (DOCS / page).read_text(encoding="utf-8")
    table = text[text.index("## Parameters") :]
    documented = set()
    for row in re.findall(r"^\|(.*)\|\s*$", table, flags=re.MULTILINE):
        cells = [c.strip() for c in row.split("|")]
        for cell in cells[:2]:  # "| parameter |" or "| layer | parameter |"
            documented |= set(re.findall(r"^`(\w+)`$", cell))
    documented -= set(LAYER_PAGES[page]) | {"both"}
    assert documented == expected, f"{page}: documented {documented}, constructor {expected}"


@pytest.mark.parametrize("page", [p for p in sorted(LAYER_PAGES) if fenced(DOCS / p, "python")])
def test_layer_page_code_runs(page: str) -> None:
    """The snippets on the layer pages build real controllers."""
    from puckboard.behaviours import Controller

    for block in fenced(DOCS / page, "python"):
        namespace: dict[str, object] = {}
        exec(compile(block, f"{page} block", "exec"), namespace)
        built = [v for v in namespace.values() if isinstance(v, Controller)]
        assert built, f"{page}: a snippet should build a Controller"


def test_sphinx_roles_become_code_spans_in_the_reference() -> None:
    sys.path.insert(0, str(DOCS))
    try:
        from griffe_rst_roles import plain_roles
    finally:
        sys.path.remove(str(DOCS))
    text = "See :class:`~puckboard.records.Proximity` and :meth:`Episode.run`, or ``x``."
    assert plain_roles(text) == "See `Proximity` and `Episode.run`, or ``x``."
    assert plain_roles(":func:`the loader <puckboard.load_controller>`") == "`the loader`"


def test_architecture_page_quotes_the_control_loop_example_verbatim() -> None:
    """The loop shown on the architectures page is the example's loop, not a paraphrase."""

    def statements(text: str) -> list[str]:
        lines = (line.split("#", 1)[0].strip() for line in text.splitlines())
        return [line for line in lines if line]

    quoted = [b for b in fenced(DOCS / "architectures.md", "python") if "sense_all" in b]
    assert quoted, "the architectures page should show the control loop"
    example = statements((ROOT / "examples" / "control_loop.py").read_text(encoding="utf-8"))
    for line in statements(quoted[0]):
        assert line in example, f"not in examples/control_loop.py: {line}"


def test_tutorial_cli_parameter_example_prints_what_the_python_one_does(capsys) -> None:
    """Step 7 shows the same experiment twice; the command must report the same run."""
    import json

    from puckboard.cli import main
    from puckboard.control.episode import run_episode

    text = (DOCS / "tutorial.md").read_text(encoding="utf-8")
    command = next(
        line
        for line in text.splitlines()
        if line.startswith("puckboard run line-follow --controller stock --set layer.LineFollow")
    )
    argv = command.split()[1:] + ["--json"]
    assert main(argv) == 0
    shown = json.loads(capsys.readouterr().out)["robots"][0]
    python = run_episode(
        "line-follow", controller="stock", duration=60, stop_early=False,
        overrides={"layer.LineFollow.inner_factor": 0.9},
    ).robots[0]  # fmt: skip
    assert shown["progress_laps"] == pytest.approx(python.progress_laps, abs=1e-4)
    assert shown["on_line_fraction"] == pytest.approx(python.on_line_fraction, abs=1e-4)
