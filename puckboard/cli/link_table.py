"""The links' control timing as ``puckboard profiles show links`` prints it: text, JSON,
and the Markdown table docs/profiles.md holds verbatim (a test keeps the two in step)."""

from __future__ import annotations

from typing import Any

from ..profile.links import LINKS, LinkTiming

__all__ = ["link_json", "link_table_markdown", "link_table_text"]


def _ms(pair: tuple[float, float]) -> str:
    low, high = (round(v * 1000, 1) for v in pair)
    return f"{low:g} ms" if low == high else f"{low:g}–{high:g} ms"


def link_json(link: LinkTiming) -> dict[str, Any]:
    return {
        "name": link.name,
        "description": link.description,
        "period_s": list(link.period),
        "latency_s": list(link.latency),
        "sources": list(link.sources),
        "assumed": link.assumed,
    }


def link_table_text(links: list[LinkTiming] | None = None, *, sources: bool = False) -> str:
    """One line per link (period, latency, assumed or not); ``sources`` adds them below."""
    chosen = list(LINKS.values()) if links is None else links
    width = max(len(link.name) for link in chosen)
    lines = [f"{'link':<{width}}  {'period':<16}latency"]
    for link in chosen:
        mark = "(assumed in part)" if link.assumed else ""
        row = f"{link.name:<{width}}  {_ms(link.period):<16}{_ms(link.latency):<14}{mark}"
        lines.append(row.rstrip())
        if sources:
            lines.append(f"  {link.description}")
            lines.extend(f"  - {s}" for s in link.sources)
    lines.append("")
    lines.append(
        "run at a link's timing: --set control.period=P --set control.latency=L "
        "(whole numbers of dt); puckboard profiles show LINK for its sources"
    )
    return "\n".join(lines)


def link_table_markdown() -> str:
    """The links table of docs/profiles.md: the ranges and what bounds them."""
    lines = [
        "| link | period | latency | sources |",
        "|---|---|---|---|",
    ]
    for link in LINKS.values():
        mark = " (assumed in part)" if link.assumed else ""
        cited = "; ".join(link.sources)
        lines.append(
            f"| `{link.name}`{mark} | {_ms(link.period)} | {_ms(link.latency)} | {cited} |"
        )
    return "\n".join(lines)
