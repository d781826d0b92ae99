"""report.html from a :class:`~.document.Document`: one self-contained page (inline CSS,
pictures as base64 data URIs, a Content-Security-Policy that forbids any request and any script).
All text goes through :func:`html.escape`."""

from __future__ import annotations

import base64
from html import escape

from vlb_gym.core.document import (Block, Cell, Code, Document, Figure, Gallery, Heading, Inline,
                                   Paragraph, Preformatted, Strong, Table)

CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'"
STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif;
       max-width: 1000px; margin: 2em auto; padding: 0 1em; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; border-bottom: 2px solid #ddd; padding-bottom: .3em; }
h2 { font-size: 1.3em; margin-top: 1.8em; border-bottom: 1px solid #eee; }
h3 { font-size: 1.05em; margin-top: 1.2em; }
table { border-collapse: collapse; margin: .8em 0; font-size: .9em; }
th, td { border: 1px solid #ccc; padding: .3em .6em; vertical-align: top; text-align: left; }
th { background: #f3f5f8; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr:nth-child(even) td { background: #fafafa; }
code { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: .88em;
       background: #f3f3f3; padding: 0 .2em; border-radius: 3px; overflow-wrap: anywhere; }
pre { background: #f6f6f6; border: 1px solid #ddd; padding: .6em; overflow-x: auto;
      font-size: .82em; }
figure { margin: 1em 0; }
figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: .85em; color: #555; }
.gallery { display: flex; flex-wrap: wrap; gap: .5em; }
.gallery figure { margin: 0; }
.gallery img { max-width: 200px; }
"""


def data_uri(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def inline(part: Inline) -> str:
    if isinstance(part, Code):
        return f"<code>{escape(part.text)}</code>"
    if isinstance(part, Strong):
        return f"<strong>{escape(part.text)}</strong>"
    return escape(str(part))


def cell(value: Cell) -> str:
    parts = value if isinstance(value, list) else [value]
    return "".join(inline(p) for p in parts)


def figure(fig: Figure, caption: bool = True) -> str:
    text = f"<figcaption>{escape(fig.caption)}</figcaption>" if caption and fig.caption else ""
    return (f'<figure><img src="{data_uri(fig.png)}" alt="{escape(fig.alt)}" '
            f'data-name="{escape(fig.name)}">{text}</figure>')


def block(item: Block) -> str:
    if isinstance(item, Heading):
        level = min(max(item.level, 1), 6)
        return f"<h{level}>{escape(item.text)}</h{level}>"
    if isinstance(item, Paragraph):
        return "<p>" + "".join(inline(p) for p in item.parts) + "</p>"
    if isinstance(item, Table):
        head = "".join(f"<th>{escape(h)}</th>" for h in item.headers)
        rows = "".join(
            "<tr>" + "".join(f'<td{" class=num" if i in item.numeric else ""}>{cell(c)}</td>'
                             for i, c in enumerate(row)) + "</tr>" for row in item.rows)
        return f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>"
    if isinstance(item, Figure):
        return figure(item)
    if isinstance(item, Gallery):
        return (f"<h3>{escape(item.title)}</h3><div class=gallery>"
                + "".join(figure(f) for f in item.figures) + "</div>")
    if isinstance(item, Preformatted):
        head = f"<p>{escape(item.summary)}:</p>" if item.summary else ""
        return f"{head}<pre>{escape(item.text)}</pre>"
    raise TypeError(f"unknown block {item!r}")


def render(document: Document) -> str:
    """The HTML page of ``document``."""
    body = "\n".join(block(b) for b in document.blocks)
    return ("<!DOCTYPE html>\n<html lang=en>\n<head>\n<meta charset=utf-8>\n"
            f'<meta http-equiv="Content-Security-Policy" content="{CSP}">\n'
            '<meta name=viewport content="width=device-width, initial-scale=1">\n'
            f"<title>{escape(document.title)}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
            f"<h1>{escape(document.title)}</h1>\n{body}\n</body>\n</html>\n")
