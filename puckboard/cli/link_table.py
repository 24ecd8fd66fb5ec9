"""The links' control timing as ``puckboard profiles show links`` prints it: text, JSON,
and the Markdown table docs/profiles.md holds verbatim (a test keeps the two in step)."""

from __future__ import annotations

from typing import Any

from ..profile.links import LINKS, LinkTiming

__all__ = ["link_cycles_markdown", "link_json", "link_table_markdown", "link_table_text"]


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
        **(
            {}
            if link.cycles is None
            else {
                "cycles": {
                    "latency_s": {
                        k: link.cycles.latency.quantile(k) for k in ("median", "p90", "max")
                    },
                    "repeated": list(link.cycles.repeated),
                    "sources": list(link.cycles.sources),
                    "assumed": link.cycles.assumed,
                }
            }
        ),
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
            if link.cycles is not None:
                lines.append(f"  cycle by cycle: {_cycles(link)}")
                lines.extend(f"  - {s}" for s in link.cycles.sources)
    lines.append("")
    lines.append(
        "run at a link's timing: --set control.period=P --set control.latency=L "
        "(whole numbers of dt); puckboard profiles show LINK for its sources"
    )
    return "\n".join(lines)


def _cycles(link: LinkTiming) -> str:
    assert link.cycles is not None
    low, high = link.cycles.repeated
    share = f"{low:.0%}" if low == high else f"{low:.0%}–{high:.0%}"
    return f"latency {link.cycles.latency.describe()}; readings repeated {share}"


def link_cycles_markdown() -> str:
    """The per-cycle table of docs/profiles.md: how each real link varies cycle by cycle
    (what ``--variation reality-gap`` draws from) and what bounds it."""
    lines = [
        "| link | each cycle's latency | readings repeated | sources |",
        "|---|---|---|---|",
    ]
    for link in LINKS.values():
        cycles = link.cycles
        if cycles is None:
            continue
        low, high = cycles.repeated
        share = f"{low:.0%}" if low == high else f"{low:.0%}–{high:.0%}"
        mark = " (assumed in part)" if cycles.assumed else ""
        lines.append(
            f"| `{link.name}`{mark} | {cycles.latency.describe()} | {share} | "
            f"{'; '.join(cycles.sources)} |"
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
