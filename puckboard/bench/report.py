"""The benchmark report: :func:`~puckboard.bench.run_suites` results as a readable table.

Suites return nested dicts, sometimes with long lists of per-run records; the table
shows each record as its own indented block and cuts long lists, while ``--json`` always
carries everything, so the table stays readable and nothing is lost.
"""

from __future__ import annotations

from typing import Any

__all__ = ["TABLE_LIST_LIMIT", "format_results"]


def format_results(results: dict[str, Any]) -> str:
    """A readable table of :func:`run_suites` results."""
    lines = []
    m = results.get("machine", {})
    lines.append(
        f"machine: {m.get('platform')} · {m.get('cpus')} CPUs · Python {m.get('python')} · "
        f"numpy {m.get('numpy')}"
    )
    for name, res in results.get("suites", {}).items():
        lines.append("")
        lines.append(f"[{name}]")
        if "skipped" in res:
            lines.append(f"  skipped: {res['skipped']}")
            continue
        _format_items(res, lines, indent="  ")
    return "\n".join(lines)


#: Longest list of records the table shows in full; ``--json`` always has everything.
TABLE_LIST_LIMIT = 8


def _format_items(res: dict[str, Any], lines: list[str], indent: str) -> None:
    width = max((len(str(k)) for k in res), default=0)
    for key, value in res.items():
        if isinstance(value, dict):
            lines.append(f"{indent}{key}:")
            _format_items(value, lines, indent + "  ")
        elif isinstance(value, (list, tuple)) and any(isinstance(v, dict) for v in value):
            lines.append(f"{indent}{key}: {len(value)} records")
            for k, item in enumerate(value[:TABLE_LIST_LIMIT]):
                lines.append(f"{indent}  [{k}]")
                if isinstance(item, dict):
                    _format_items(item, lines, indent + "    ")
                else:
                    lines.append(f"{indent}    {_fmt(item)}")
            if len(value) > TABLE_LIST_LIMIT:
                lines.append(f"{indent}  ... {len(value) - TABLE_LIST_LIMIT} more (see --json)")
        else:
            lines.append(f"{indent}{key:<{width}}  {_fmt(value)}")


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        if value == 0 or 0.01 <= abs(value) < 1e6:
            return f"{value:,.2f}"
        return f"{value:.3g}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    return str(value)
