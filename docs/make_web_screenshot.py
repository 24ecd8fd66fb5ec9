"""Regenerate docs/img/web-view.png: the live web view of the two-robot pass, mid-run.

Needs Chromium (Debian's ``chromium``) and ``puckboard[web]``. Runs the scene at eight
times real time with the web view, opens it in headless Chromium at projector size,
waits for the robots to meet, opens the right robot's panel and takes the picture::

    python docs/make_web_screenshot.py
"""

from __future__ import annotations

import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "web"))

from browser import Browser, chromium  # noqa: E402

from puckboard.control.episode import Episode  # noqa: E402
from puckboard.web import watch_episode  # noqa: E402

OUT = ROOT / "docs" / "img" / "web-view.png"


def main() -> None:
    binary = chromium()
    if binary is None:
        raise SystemExit("no Chromium found; install Debian's 'chromium' package")
    episode = Episode("two-robot-pass", seed=0)
    view = watch_episode(episode, port=0, speed=8.0)
    threading.Thread(target=episode.run, args=(120.0,), daemon=True).start()
    try:
        with Browser(binary, width=1600, height=900) as browser:
            browser.open(view.url)
            browser.wait_for("window.state && state.frame && state.frame.t > 1")
            browser.evaluate(
                "document.querySelector('#robots tbody tr[data-robot=\"right\"]').click()"
            )
            browser.wait_for("window.state && state.frame && state.frame.t > 36", timeout=60)
            time.sleep(0.6)  # the panel's next refresh
            browser.screenshot(str(OUT))
    finally:
        view.close()
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
