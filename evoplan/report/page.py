"""The report's sections assembled into one HTML page with plotly's JavaScript inlined once."""

from __future__ import annotations

import html
from dataclasses import dataclass
from typing import Any

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 1.5em auto; max-width: 1150px; color: #222; }
h1 { font-size: 1.4em; } h2 { font-size: 1.15em; margin-top: 1.6em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.5em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 3px 9px; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
p.note { color: #555; font-size: 0.9em; }
"""


@dataclass
class Section:
    """A titled part of the page: plotly figures, tables (header, rows) and notes, in order."""

    title: str
    items: list[Any]


def table(header: list[str], rows: list[list[Any]]) -> str:
    """An HTML table; numbers right-aligned and printed with 6 significant digits."""
    def cell(v):
        if isinstance(v, float):
            return f'<td class="num">{v:.6g}</td>'
        if isinstance(v, int) and not isinstance(v, bool):
            return f'<td class="num">{v}</td>'
        return f"<td>{html.escape(str(v))}</td>"

    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(cell(v) for v in row) + "</tr>" for row in rows)
    return f'<div style="overflow-x:auto"><table><tr>{head}</tr>{body}</table></div>'


def note(text: str) -> str:
    return f'<p class="note">{html.escape(text)}</p>'


def page(title: str, sections: list[Section]) -> str:
    """One HTML document; the first figure carries plotly.js, the others reuse it."""
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
             f"<style>{_STYLE}</style></head><body><h1>{html.escape(title)}</h1>"]
    inlined = False
    for section in sections:
        parts.append(f"<h2>{html.escape(section.title)}</h2>")
        for item in section.items:
            if isinstance(item, str):
                parts.append(item)
                continue
            parts.append(item.to_html(full_html=False, include_plotlyjs=not inlined,
                                      config={"displaylogo": False, "responsive": True}))
            inlined = True
    parts.append("</body></html>")
    return "".join(parts)
