"""A tiny document model rendered to one static HTML page and one Markdown file.

Blocks: :class:`Para`, :class:`Table`, :class:`Figure`, :class:`Note` (a
"no data" notice), :class:`MarkdownText` (a .md file included verbatim, its
headings and pipe tables converted for the HTML page). Image paths are
relative to the report directory, so the report can be moved as a whole.
"""

from __future__ import annotations

import html
import re
from dataclasses import dataclass, field


@dataclass
class Para:
    text: str


@dataclass
class Note:
    text: str


@dataclass
class Table:
    headers: list[str]
    rows: list[list[str]]
    caption: str = ""


@dataclass
class Figure:
    src: str  # relative to the report directory
    caption: str
    data: str | None = None  # the plotted numbers (CSV), relative to the report directory


@dataclass
class MarkdownText:
    text: str
    source: str = ""


@dataclass
class Raw:
    """A fragment of HTML (an interactive player or viewer) and what Markdown says instead."""
    html: str
    markdown: str = ""


@dataclass
class Section:
    title: str
    blocks: list = field(default_factory=list)
    level: int = 2

    def add(self, block) -> Section:
        self.blocks.append(block)
        return self


def _slug(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")


# ------------------------------------------------------------------ markdown
def _md_cell(s: str) -> str:
    return str(s).replace("|", "\\|").replace("\n", " ")


def to_markdown(title: str, intro: list, sections: list[Section]) -> str:
    out = [f"# {title}", ""]
    for b in intro:
        out += _md_block(b)
    out += ["## Contents", ""]
    out += [f"{'  ' * (s.level - 2)}- [{s.title}](#{_slug(s.title)})" for s in sections]
    out.append("")
    for s in sections:
        out += [f"{'#' * s.level} {s.title}", ""]
        for b in s.blocks:
            out += _md_block(b)
    return "\n".join(out).rstrip() + "\n"


def _md_block(b) -> list[str]:
    if isinstance(b, Para):
        return [b.text, ""]
    if isinstance(b, Note):
        return [f"> **No data:** {b.text}", ""]
    if isinstance(b, Table):
        lines = []
        if b.caption:
            lines += [f"*{b.caption}*", ""]
        lines.append("| " + " | ".join(_md_cell(h) for h in b.headers) + " |")
        lines.append("|" + "|".join("---" for _ in b.headers) + "|")
        lines += ["| " + " | ".join(_md_cell(c) for c in row) + " |" for row in b.rows]
        return lines + [""]
    if isinstance(b, Figure):
        data = f" ([data]({b.data}))" if b.data else ""
        return [f"![{b.caption}]({b.src})", "", f"*{b.caption}*{data}", ""]
    if isinstance(b, Raw):
        return [b.markdown, ""] if b.markdown else []
    if isinstance(b, MarkdownText):
        text = re.sub(r"^(#+)", lambda m: "#" * min(6, len(m.group(1)) + 2), b.text, flags=re.M)
        return ([f"*From `{b.source}`:*", ""] if b.source else []) + [text.strip(), ""]
    raise TypeError(type(b))


# ------------------------------------------------------------------ html
CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Helvetica,Arial,sans-serif;max-width:1200px;margin:2em auto;
padding:0 1em;color:#222;line-height:1.45}
h1{border-bottom:2px solid #444}h2{border-bottom:1px solid #bbb;margin-top:2em}
table{border-collapse:collapse;margin:0.6em 0 1.2em;font-size:0.9em}
th,td{border:1px solid #ccc;padding:3px 7px;text-align:right}th{background:#f0f0f0}
td:first-child,th:first-child{text-align:left}
caption{caption-side:top;text-align:left;font-style:italic;padding-bottom:4px}
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}
figcaption{font-style:italic;font-size:0.9em}
.note{background:#fff6d6;border-left:4px solid #e0b000;padding:6px 10px}
pre{background:#f6f6f6;padding:8px;overflow-x:auto}
nav ul{columns:2}
"""


def _inline(text: str) -> str:
    t = html.escape(text)
    t = re.sub(r"`([^`]+)`", r"<code>\1</code>", t)
    t = re.sub(r"\*\*([^*]+)\*\*", r"<b>\1</b>", t)
    return t


def _html_table(headers, rows, caption="") -> str:
    cap = f"<caption>{_inline(caption)}</caption>" if caption else ""
    head = "".join(f"<th>{_inline(str(h))}</th>" for h in headers)
    body = "".join("<tr>" + "".join(f"<td>{_inline(str(c))}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table>{cap}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def markdown_to_html(text: str) -> str:
    """Headings, pipe tables, fenced code, images and paragraphs: enough for the .md files we include."""
    out, para, table, code = [], [], [], None

    def flush():
        nonlocal para, table
        if para:
            out.append(f"<p>{_inline(' '.join(para))}</p>")
            para = []
        if table:
            rows = [[c.strip() for c in ln.strip().strip("|").split("|")] for ln in table]
            rows = [r for r in rows if not all(re.fullmatch(r":?-{2,}:?", c) for c in r)]
            if rows:
                out.append(_html_table(rows[0], rows[1:]))
            table = []

    for line in text.splitlines():
        if code is not None:
            if line.strip().startswith("```"):
                out.append(f"<pre>{html.escape(chr(10).join(code))}</pre>")
                code = None
            else:
                code.append(line)
            continue
        if line.strip().startswith("```"):
            flush()
            code = []
        elif line.lstrip().startswith("|"):
            if para:
                flush()
            table.append(line)
        elif m := re.fullmatch(r"\s*!\[([^\]]*)\]\(([^)\s]+)\)\s*", line):
            flush()
            out.append(f'<figure><img src="{html.escape(m.group(2))}" alt="{html.escape(m.group(1))}" '
                       f'loading="lazy"><figcaption>{_inline(m.group(1))}</figcaption></figure>')
        elif m := re.match(r"^(#{1,6})\s+(.*)", line):
            flush()
            lvl = min(6, len(m.group(1)) + 2)
            out.append(f"<h{lvl}>{_inline(m.group(2))}</h{lvl}>")
        elif not line.strip():
            flush()
        else:
            if table:
                flush()
            para.append(line.strip())
    flush()
    if code is not None:
        out.append(f"<pre>{html.escape(chr(10).join(code))}</pre>")
    return "\n".join(out)


def to_html(title: str, intro: list, sections: list[Section]) -> str:
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             f"<title>{html.escape(title)}</title><style>{CSS}</style></head><body>",
             f"<h1>{html.escape(title)}</h1>"]
    parts += [_html_block(b) for b in intro]
    parts.append("<nav><h2>Contents</h2><ul>" + "".join(
        f'<li><a href="#{_slug(s.title)}">{html.escape(s.title)}</a></li>' for s in sections) + "</ul></nav>")
    for s in sections:
        parts.append(f'<h{s.level} id="{_slug(s.title)}">{html.escape(s.title)}</h{s.level}>')
        parts += [_html_block(b) for b in s.blocks]
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def _html_block(b) -> str:
    if isinstance(b, Para):
        return f"<p>{_inline(b.text)}</p>"
    if isinstance(b, Note):
        return f'<p class="note"><b>No data:</b> {_inline(b.text)}</p>'
    if isinstance(b, Table):
        return _html_table(b.headers, b.rows, b.caption)
    if isinstance(b, Figure):
        data = f' (<a href="{html.escape(b.data)}">data, CSV</a>)' if b.data else ""
        return (f'<figure><img src="{html.escape(b.src)}" alt="{html.escape(b.caption)}" loading="lazy">'
                f"<figcaption>{_inline(b.caption)}{data}</figcaption></figure>")
    if isinstance(b, Raw):
        return b.html
    if isinstance(b, MarkdownText):
        src = f"<p><i>From <code>{html.escape(b.source)}</code>:</i></p>" if b.source else ""
        return src + markdown_to_html(b.text)
    raise TypeError(type(b))
