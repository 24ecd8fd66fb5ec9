"""``leaderboard.html``: the class's ranking as one offline page.

One file that opens with a double click, from a course page or a USB stick: its styles
are inline, it runs no script and fetches nothing (a Content-Security-Policy in the file
forbids every request). Its links are relative: each entry's replays
(``replays/*.html``, the offline player of ``puckboard replay --html``) sit beside it in
the output folder.

The page states the ranking rule, lists every entry with its rank (from 1; the
baselines highlighted and unranked), when it was graded, its success rate with the
95 % Wilson interval overall, in its worst cell and in each graded cell, its median
progress, its failures, its verdict and remarks; then the graded cells as the challenge
describes them (with their seeds once revealed), the practice set, and what each
verdict means.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from datetime import datetime, timezone
from typing import TYPE_CHECKING

from .spec import RANKING_KEYS
from .standings import VERDICTS, Standing

if TYPE_CHECKING:
    from .result import Grading

__all__ = ["leaderboard_html"]

_CSP = (
    "default-src 'none'; style-src 'unsafe-inline'; img-src data:; base-uri 'none'; "
    "form-action 'none'"
)

_STYLE = """
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto;
       max-width: 100em; padding: 0 1em; color: #1d232b; }
p, ul, ol { max-width: 60em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { font-size: 1.15em; margin-top: 2em; }
.meta { color: #5b6572; }
table { border-collapse: collapse; width: 100%; margin-top: 0.5em; }
th, td { padding: 0.35em 0.6em; border-bottom: 1px solid #dde2e8; text-align: left;
         vertical-align: top; }
th { background: #f3f5f8; font-weight: 600; white-space: nowrap; }
td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
tr.baseline td { background: #fff6dc; }
tr.baseline td.entry::after { content: " baseline"; font-size: 0.8em; color: #8a6d00;
         margin-left: 0.4em; }
tr.unranked td { color: #5b6572; }
.ci { color: #5b6572; font-size: 0.8em; display: block; }
td.when { white-space: nowrap; font-size: 0.85em; color: #5b6572; }
td.replays { white-space: nowrap; }
.verdict { font-weight: 600; }
.verdict.graded { color: #1f7a3a; }
.remarks, .why { font-size: 0.85em; color: #5b6572; }
code { background: #f3f5f8; padding: 0 0.25em; border-radius: 3px; }
"""


def _e(text: object) -> str:
    return html.escape(str(text), quote=True)


def _rate(successes: int, episodes: int, rate: float, low: float, high: float) -> str:
    return (
        f"{100 * rate:.0f} % <span class=ci>{successes}/{episodes} · "
        f"[{100 * low:.0f}, {100 * high:.0f}]</span>"
    )


def _row(s: Standing, cells: Sequence[str]) -> str:
    classes = [c for c, on in (("baseline", s.baseline), ("unranked", s.rank is None)) if on]
    rank = "" if s.rank is None else str(s.rank)
    cols = [f'<td class="n rank">{rank}</td>', f'<td class="entry">{_e(s.name)}</td>']
    day, _, hour = (s.graded_at or "").rstrip("Z").partition("T")
    when = f"{_e(day)}<br>{_e(hour[:5])} UTC" if day else ""
    cols.append(f'<td class="when">{when}</td>')
    overall = s.overall
    if overall is None:
        cols += ['<td class="n">-</td>'] * (2 + len(cells))
    else:
        cols.append(
            '<td class="n overall">'
            + _rate(
                overall.successes,
                overall.episodes,
                overall.success_rate,
                overall.ci95_low,
                overall.ci95_high,
            )
            + "</td>"
        )
        cols.append(f'<td class="n worst">{100 * s.worst_cell:.0f} %</td>')
        by_cell = dict(s.cells)
        for cell in cells:
            g = by_cell[cell]
            cols.append(
                '<td class="n cell">'
                + _rate(g.successes, g.episodes, g.success_rate, g.ci95_low, g.ci95_high)
                + "</td>"
            )
    cols.append(
        f'<td class="n progress">{s.median_progress:.2f}</td>'
        if overall
        else '<td class="n">-</td>'
    )
    failures = ", ".join(f"{_e(k)} {v}" for k, v in s.failures.items()) or "-"
    cols.append(f'<td class="failures">{failures}</td>')
    why = f'<div class="why">{_e(s.verdict_text)}</div>' if s.verdict_text else ""
    remarks = f'<div class="remarks">{_e("; ".join(s.remarks))}</div>' if s.remarks else ""
    cols.append(
        f'<td><span class="verdict {_e(s.verdict)}">{_e(s.verdict)}</span>{why}{remarks}</td>'
    )
    links = [
        f'<a href="{_e(s.replays[which])}" class="replay {which}">{label}</a>'
        for which, label in (("worst", "worst"), ("success", "success"))
        if which in s.replays
    ]
    cols.append(f'<td class="replays">{" · ".join(links) or "-"}</td>')
    return f'<tr class="{" ".join(classes)}">{"".join(cols)}</tr>'


def _table(standings: Sequence[Standing], cells: Sequence[str], table_id: str) -> str:
    head = [
        "rank",
        "entry",
        "graded",
        "success",
        "worst cell",
        *cells,
        "median progress",
        "failures",
        "verdict",
        "replays",
    ]
    header = "".join(f"<th>{_e(h)}</th>" for h in head)
    body = "\n".join(_row(s, cells) for s in standings)
    head_row = f"<thead><tr>{header}</tr></thead>"
    return f'<table id="{table_id}">{head_row}\n<tbody>\n{body}\n</tbody></table>'


def leaderboard_html(grading: Grading) -> str:
    """The page for ``grading`` (see the module docstring)."""
    challenge = grading.challenge
    cells = [c.name for c in challenge.graded]
    made = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    if grading.view == "final":
        view = f"final ranking (versions handed in by {_e(grading.final_at)})"
    else:
        view = "latest versions (no final ranking frozen yet)"
    rule = "".join(f"<li>{_e(RANKING_KEYS[k])}</li>" for k in challenge.ranking)
    parts = [
        "<!doctype html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f'<meta http-equiv="Content-Security-Policy" content="{_CSP}">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{_e(challenge.title)} — leaderboard</title>",
        f"<style>{_STYLE}</style></head><body>",
        f"<h1>{_e(challenge.title)}</h1>",
        f'<p class="description">{_e(challenge.description)}</p>',
        f'<p class="meta">challenge <code>{_e(challenge.name)}</code> · {len(cells)} graded '
        f"cells × {challenge.episodes} episodes, on seeds drawn from the lecturer's secret · "
        f"{view} · page made {made}</p>",
        f'<section id="rule"><h2>How entries are ranked</h2><p>By, in turn:</p><ol>{rule}</ol>'
        "<p>Equal figures share a rank. Success rates come with their 95 % Wilson interval "
        "(successes/episodes · [low, high] %). Baselines, the shipped controllers, are "
        "highlighted and take no rank. An entry the pre-flight check refused is listed, "
        "unranked, with the reason.</p></section>",
        f'<h2 id="ranking">{"Final ranking" if grading.view == "final" else "Ranking"}</h2>',
        _table(grading.standings, cells, "leaderboard"),
    ]
    if grading.latest is not None:
        parts += [
            '<h2 id="after">Latest versions (after the final ranking; they do not change it)</h2>',
            _table(grading.latest, cells, "latest"),
        ]
    parts.append('<section id="cells"><h2>Graded cells</h2><ul>')
    for cell in challenge.graded:
        seeds = ""
        if grading.seeds is not None:
            seeds = f" — seeds {', '.join(str(s) for s in grading.seeds[cell.name])}"
        parts.append(f"<li><b>{_e(cell.name)}</b>: {_e(cell.describe())}{_e(seeds)}</li>")
    parts.append("</ul><h2>Practice cells</h2><ul>")
    seeds_text = f"{challenge.practice_seeds.start}:{challenge.practice_seeds.stop}"
    for cell in challenge.practice:
        parts.append(f"<li><b>{_e(cell.name)}</b>: {_e(cell.describe())} (seeds {seeds_text})</li>")
    parts.append("</ul></section>")
    legend = "".join(f"<li><b>{_e(k)}</b>: {_e(v)}</li>" for k, v in VERDICTS.items())
    parts.append(f'<section id="verdicts"><h2>Verdicts</h2><ul>{legend}</ul></section>')
    parts.append("</body></html>\n")
    return "\n".join(parts)
