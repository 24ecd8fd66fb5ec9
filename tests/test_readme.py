"""The README's promises: two set-up commands first, and a layer example that works."""

from __future__ import annotations

import re
from pathlib import Path

from puckboard.control.episode import run_episode

README = Path(__file__).resolve().parent.parent / "README.md"


def test_readme_opens_with_the_two_setup_commands():
    text = README.read_text(encoding="utf-8")
    first_block = re.search(r"```bash\n(.*?)```", text, re.S)
    assert first_block is not None
    assert text.index("```bash") < text.index("\n## ")  # before any section
    commands = [line for line in first_block.group(1).splitlines() if line.strip()]
    assert len(commands) == 2
    assert commands[0].endswith("puckboard run")
    assert "pytest" in commands[1]


def test_readme_layer_example_passes_the_two_robot_pass(tmp_path):
    text = README.read_text(encoding="utf-8")
    code = re.search(r"```python\n(.*?)```", text, re.S)
    assert code is not None
    module = tmp_path / "mylayers.py"
    module.write_text(code.group(1), encoding="utf-8")
    result = run_episode("two-robot-pass", controller=f"{module}:make", seed=0)
    assert result.success, (result.failure, result.events)


def test_readme_sample_output_is_what_puckboard_run_prints(capsys):
    """Every line the README shows for 'puckboard run' (numbers aside, '...' elided
    lines skipped) is in the real output, events block included."""
    from puckboard.cli import main

    text = README.read_text(encoding="utf-8")
    block = re.search(
        r"```console\n\$ puckboard run\n(.*?)\$ puckboard run --controller", text, re.S
    )
    assert block is not None
    shown = [line for line in block.group(1).splitlines() if line.strip() not in ("", "...")]
    assert "events:" in shown
    assert main(["run"]) == 0
    out = capsys.readouterr().out

    def words(line: str) -> str:
        return re.sub(r"\d+(\.\d+)?", "#", " ".join(line.split()))

    printed = {words(line) for line in out.splitlines()}
    for line in shown:
        assert words(line) in printed, (line, out)
