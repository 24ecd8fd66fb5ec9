"""The page laid out for a room and for a phone, measured in a real headless browser:
robot names on the arena never sit on an obstacle, a robot or each other; at phone width
the footer follows the events and a robot's name stays on one line; an event names its
robot apart from the event's words. The recorded two-robot pass is replayed (it has every
pose of the run, so the names can be checked at every moment of it). Skipped where no
Chromium is found."""

from __future__ import annotations

import pytest
from browser import Browser, chromium
from recordings import recorded_run

from puckboard.recording.recorder import load_recording
from puckboard.web.export import write_replay_html

BINARY = chromium()
pytestmark = pytest.mark.skipif(
    BINARY is None,
    reason="no Chromium found (chromium, chromium-browser, google-chrome); install Debian's "
    "'chromium' package, as .ci/run does, to run the browser tests",
)

READY = "window.state && state.player && state.readyAt"
#: (width, height, phone) of the windows the lecturer's faults were seen at
WINDOWS = [(1400, 900, False), (412, 915, True)]


@pytest.fixture(scope="module")
def replay_page(tmp_path_factory):
    folder = tmp_path_factory.mktemp("layout")
    rec = load_recording(recorded_run("two-robot-pass"))
    return rec, write_replay_html(rec, folder / "pass.html")


def open_page(browser: Browser, path, width: int, height: int, phone: bool) -> None:
    browser.emulate(width, height, mobile=phone)
    browser.open(path.as_uri())
    browser.wait_for(READY)


# Every tick (a stride through the run), every name the arena canvas writes, with the box
# its letters cover as the canvas itself measures them (its own fillText and measureText,
# watched from outside the page's code), against the discs of the obstacles and robots.
NAME_CLASHES = """(() => {
  const calls = [], fill = CanvasRenderingContext2D.prototype.fillText;
  CanvasRenderingContext2D.prototype.fillText = function (text, x, y) {
    if (this.canvas.id === 'arena') {
      const m = this.measureText(text);
      calls.push({ text, box: [x, y - m.actualBoundingBoxAscent, x + m.width,
                               y + m.actualBoundingBoxDescent] });
    }
    return fill.apply(this, arguments);
  };
  const sc = state.scene, v = state.view, p = state.player, out = [];
  const disc = (box, u, w, r) => Math.hypot(Math.max(box[0], Math.min(u, box[2])) - u,
                                            Math.max(box[1], Math.min(w, box[3])) - w) < r;
  let checked = 0;
  for (let i = 0; i < p.times.length; i += STRIDE) {
    calls.length = 0;
    p.show(i);
    const robots = state.frame.robots.map(
      (r, k) => [r.name, ...px(r.pose[0], r.pose[1]), sc.robots[k].radius * v.s]);
    const names = calls.filter(c => robots.some(r => r[0] === c.text));
    if (names.length !== robots.length) out.push([i, 'names drawn', names.map(c => c.text)]);
    for (const c of names) {
      checked++;
      for (const ob of sc.obstacles) {
        const [u, w] = px(ob.circle[0], ob.circle[1]);
        if (disc(c.box, u, w, ob.circle[2] * v.s)) out.push([i, c.text, 'on obstacle', ob.name]);
      }
      for (const [name, u, w, r] of robots) {
        if (disc(c.box, u, w, r)) out.push([i, c.text, 'on robot', name]);
        const far = Math.hypot(Math.max(c.box[0], Math.min(u, c.box[2])) - u,
                               Math.max(c.box[1], Math.min(w, c.box[3])) - w);
        if (name === c.text && far > r + 12 * v.ratio) {
          out.push([i, c.text, 'away from its robot', far - r]);
        }
      }
      for (const d of names) {
        const b = d.box, a = c.box;
        if (d !== c && a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]) {
          out.push([i, c.text, 'on name', d.text]);
        }
      }
    }
  }
  CanvasRenderingContext2D.prototype.fillText = fill;
  return { checked, clashes: out };
})()"""


@pytest.mark.parametrize(("width", "height", "phone"), WINDOWS)
def test_robot_names_never_sit_on_an_obstacle_a_robot_or_another_name(
    replay_page, width, height, phone
):
    rec, path = replay_page
    assert all(ob.radius > 0 for ob in rec.scene.obstacles)  # discs: what the check measures
    stride = 3
    with Browser(BINARY) as browser:
        open_page(browser, path, width, height, phone)
        found = browser.evaluate(NAME_CLASHES.replace("STRIDE", str(stride)))
    assert found["checked"] == 2 * len(range(0, len(rec), stride))
    assert found["clashes"] == [], found["clashes"]


def test_on_a_phone_the_footer_follows_the_events_and_names_stay_on_one_line(replay_page):
    rec, path = replay_page
    longest = max(rec.layer_names, key=len)
    tick = next(
        i for i in range(len(rec)) if longest in (rec.robot(n).layer_at(i) for n in rec.robot_names)
    )
    with Browser(BINARY) as browser:
        open_page(browser, path, 412, 915, True)
        browser.evaluate(f"state.player.seek({tick})")
        assert longest in browser.evaluate(
            "Array.from(document.querySelectorAll('#robots .layer')).map(e => e.textContent)"
        )
        boxes = browser.evaluate("""(() => {
          const box = e => {
            const b = e.getBoundingClientRect();
            return [b.left, b.top, b.right, b.bottom];
          };
          return {
            footer: box(document.getElementById('connection')),
            events: Array.from(document.querySelectorAll('#events li')).map(box),
            table: box(document.getElementById('robots')),
            page: [document.documentElement.scrollWidth, window.innerWidth],
            // per robot row: the tops of the lines its name cell's contents sit on
            names: Array.from(document.querySelectorAll('#robots tbody td:first-child')).map(td => {
              const r = document.createRange(); r.selectNodeContents(td);
              return Array.from(r.getClientRects())
                .filter(q => q.width > 0).map(q => Math.round(q.top));
            }),
          };
        })()""")
    footer, events = boxes["footer"], boxes["events"]
    assert len(events) == len(rec.meta["events"])
    for li in [*events, boxes["table"]]:
        overlap = min(footer[2], li[2]) > max(footer[0], li[0]) and min(footer[3], li[3]) > max(
            footer[1], li[1]
        )
        assert not overlap, (footer, li)
    assert footer[1] >= events[-1][3]  # below the last event: the page scrolls to it
    assert boxes["page"][0] <= boxes["page"][1]  # nothing wider than the phone
    for tops in boxes["names"]:
        assert len(tops) >= 2 and max(tops) - min(tops) <= 3, tops  # dot and name, one line


def test_an_event_names_its_robot_apart_from_the_events_words(replay_page):
    """Robots called left and right: '5.0 s  left: left the line', the name in the
    robot's colour and set off by a colon, never 'left left the line'."""
    rec, path = replay_page
    with Browser(BINARY) as browser:
        open_page(browser, path, 1400, 900, False)
        items = browser.evaluate("""Array.from(document.querySelectorAll('#events li')).map(li => {
          const who = li.querySelector('.who');
          return [li.textContent, who && who.textContent, who && getComputedStyle(who).color,
                  who && getComputedStyle(who).fontWeight];
        })""")
        colours = browser.evaluate(
            "Object.fromEntries(state.scene.robots.map(r => [r.name, r.colour]))"
        )
    events = sorted(rec.meta["events"], key=lambda e: e["time_s"])
    assert len(items) == len(events)
    for (text, who, colour, weight), e in zip(items, events):
        from puckboard.viz.style import event_label

        words = event_label(e["kind"])
        if e.get("robot"):
            assert text == f"{e['time_s']:.1f} s  {e['robot']}: {words}"
            assert who == e["robot"] and int(weight) >= 600
            hexa = colours[e["robot"]].lstrip("#")
            assert colour == "rgb({}, {}, {})".format(
                *(int(hexa[k : k + 2], 16) for k in (0, 2, 4))
            )
        else:
            assert text == f"{e['time_s']:.1f} s  {words}" and who is None
