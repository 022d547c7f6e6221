"""The report's document model: headings, paragraphs, tables, figures and
preformatted text, rendered to Markdown and to HTML from the same blocks."""

from __future__ import annotations

import html
import math
import re
from typing import Any, Sequence

__all__ = ["Doc", "pct"]


class Doc:
    """Blocks rendered to both Markdown and HTML."""

    def __init__(self) -> None:
        self.blocks: list[tuple[str, Any]] = []

    def h(self, level: int, text: str) -> None:
        self.blocks.append(("h", (level, text)))

    def p(self, text: str) -> None:
        self.blocks.append(("p", text))

    def section(self, title: str, text: str) -> None:
        """A section's heading (level 2) and its first paragraph, ``text`` with its
        line breaks and indents read as single spaces."""
        self.h(2, title)
        self.p(" ".join(text.split()))

    def table(self, header: Sequence[str], rows: Sequence[Sequence[Any]]) -> None:
        self.blocks.append(("table", (list(header), [[_cell(c) for c in r] for r in rows])))

    def img(self, path: str, alt: str) -> None:
        self.blocks.append(("img", (path, alt)))

    def pre(self, text: str) -> None:
        self.blocks.append(("pre", text))

    def markdown(self) -> str:
        out: list[str] = []
        for kind, v in self.blocks:
            if kind == "h":
                out.append("#" * v[0] + " " + v[1])
            elif kind == "p":
                out.append(v)
            elif kind == "table":
                head, rows = v
                out.append("| " + " | ".join(h.replace("|", "\\|") for h in head) + " |")
                out.append("|" + "|".join("---" for _ in head) + "|")
                out += ["| " + " | ".join(str(c).replace("|", "\\|") for c in r) + " |" for r in rows]
            elif kind == "img":
                out.append(f"![{v[1]}]({v[0]})")
            elif kind == "pre":
                out.append("```text\n" + v + "\n```")
            out.append("")
        return "\n".join(out)

    def html(self, title: str) -> str:
        e = html.escape
        out = [
            "<!DOCTYPE html>",
            '<html lang="en"><head><meta charset="utf-8">',
            f"<title>{e(title)}</title>",
            "<style>body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;"
            "line-height:1.45;color:#222}table{border-collapse:collapse;margin:1em 0;font-size:0.9em}"
            "td,th{border:1px solid #bbb;padding:3px 7px;text-align:left;vertical-align:top}"
            "th{background:#eee}img{max-width:100%;border:1px solid #ddd;margin:0.5em 0}"
            "pre{background:#f6f6f6;padding:0.6em;overflow-x:auto;font-size:0.8em}code{background:#f3f3f3}</style>",
            "</head><body>",
        ]
        for kind, v in self.blocks:
            if kind == "h":
                out.append(f"<h{v[0]}>{_inline(v[1])}</h{v[0]}>")
            elif kind == "p":
                out.append(f"<p>{_inline(v)}</p>")
            elif kind == "table":
                head, rows = v
                out.append("<table><tr>" + "".join(f"<th>{_inline(h)}</th>" for h in head) + "</tr>")
                out += ["<tr>" + "".join(f"<td>{_inline(str(c))}</td>" for c in r) + "</tr>" for r in rows]
                out.append("</table>")
            elif kind == "img":
                out.append(f'<p><img src="{e(v[0])}" alt="{e(v[1])}"></p>')
            elif kind == "pre":
                out.append(f"<pre>{e(v)}</pre>")
        out.append("</body></html>")
        return "\n".join(out)


def _inline(text: str) -> str:
    """Escapes, then renders `code`, **bold** and [links](relative/path.html)."""
    t = html.escape(text)
    t = re.sub(r"`([^`]+)`", r"<code>\1</code>", t)
    t = re.sub(r"\*\*([^*]+)\*\*", r"<b>\1</b>", t)
    t = re.sub(r"\[([^\]]+)\]\(([^)\s]+)\)", r'<a href="\2">\1</a>', t)
    return t


def _cell(x: Any) -> str:
    if x is None:
        return "—"
    if isinstance(x, float):
        if math.isnan(x):
            return "—"
        if x == 0:
            return "0"
        a = abs(x)
        return f"{x:.3g}" if 1e-3 <= a < 1e5 else f"{x:.2e}"
    return str(x)


def pct(x: float) -> str:
    return f"{100 * x:.2f} %"
