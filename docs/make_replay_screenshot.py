"""Regenerate docs/img/replay.png: the one-file replay of the two-robot pass, paused where
the robots meet, with the right robot's behaviour tree open.

Needs Chromium (Debian's ``chromium``). Records the scene (seed 0, improved controller),
writes the player as one HTML file, opens it from disk in headless Chromium with the
network switched off, clicks the first "passed the other robot" event and the right
robot, and takes the picture. It also prints the file's size and how long the page took
to become usable (``performance.now()`` when the player had drawn its first frame)::

    python docs/make_replay_screenshot.py
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "web"))

from browser import Browser, chromium  # noqa: E402

from puckboard.control.episode import Episode  # noqa: E402
from puckboard.recording.recorder import Recorder  # noqa: E402
from puckboard.web.export import write_replay_html  # noqa: E402

OUT = ROOT / "docs" / "img" / "replay.png"


def main() -> None:
    binary = chromium()
    if binary is None:
        raise SystemExit("no Chromium found; install Debian's 'chromium' package")
    episode = Episode("two-robot-pass", seed=0)
    recorder = Recorder.for_episode(episode).attach(episode)
    episode.run()
    rec = recorder.close()
    with tempfile.TemporaryDirectory() as folder:
        page = write_replay_html(rec, Path(folder) / "two-robot-pass.html")
        size = page.stat().st_size
        with Browser(binary, width=1600, height=900) as browser:
            browser.call("Network.enable")
            browser.call("Network.emulateNetworkConditions", offline=True, latency=0,
                         downloadThroughput=-1, uploadThroughput=-1)  # fmt: skip
            browser.open(page.as_uri())
            ready = browser.wait_for("window.state && state.player && state.readyAt")
            browser.evaluate(
                "Array.from(document.querySelectorAll('#events li'))"
                ".find(e => e.textContent.includes('passed the other robot')).click()"
            )
            browser.evaluate(
                "document.querySelector('#robots tbody tr[data-robot=\"right\"]').click()"
            )
            browser.screenshot(str(OUT))
    print(f"wrote {OUT}; the page is {size / 1e6:.2f} MB and was ready {ready:.0f} ms after "
          "it started loading")  # fmt: skip


if __name__ == "__main__":
    main()
