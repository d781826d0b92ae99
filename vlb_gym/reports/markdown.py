"""report.md from a :class:`~.document.Document`: GitHub-flavoured markdown, pictures as files
in ``figures/`` next to it. Text is escaped so that untrusted strings stay text, and control
characters (a terminal escape in a stored reason) are written as visible escapes, so that
``cat report.md`` shows them instead of obeying them."""

from __future__ import annotations

import re

from vlb_gym.core.document import (Block, Cell, Code, Document, Figure, Gallery, Heading, Inline,
                                   Paragraph, Preformatted, Strong, Table)
from vlb_gym.core.text import escape_controls

FIGURE_DIR = "figures"
_SPECIAL = re.compile(r"([\\`*_\[\]|~])")


def escape(text: str) -> str:
    """Plain text for markdown: one line, markdown punctuation backslash-escaped, and ``<``,
    ``&`` as entities (renderers pass raw HTML through)."""
    text = re.sub(r"\s+", " ", str(text))
    text = text.replace("&", "&amp;").replace("<", "&lt;")
    return _SPECIAL.sub(r"\\\1", text)


def code(text: str) -> str:
    """An inline code span that no backtick of ``text`` can close (``|`` escaped for tables)."""
    text = re.sub(r"\s+", " ", str(text)).replace("|", "\\|")
    longest = max((len(run) for run in re.findall(r"`+", text)), default=0)
    fence = "`" * (longest + 1)
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def inline(part: Inline) -> str:
    if isinstance(part, Code):
        return code(part.text)
    if isinstance(part, Strong):
        return f"**{escape(part.text)}**" if part.text.strip() else ""
    return escape(part)


def cell(value: Cell) -> str:
    parts = value if isinstance(value, list) else [value]
    return "".join(inline(p) for p in parts) or " "


def figure(fig: Figure) -> str:
    return f"![{escape(fig.alt)}]({FIGURE_DIR}/{fig.name})"


def block(item: Block) -> str:
    if isinstance(item, Heading):
        return "#" * item.level + " " + escape(item.text)
    if isinstance(item, Paragraph):
        return "".join(inline(p) for p in item.parts)
    if isinstance(item, Table):
        align = ["---:" if i in item.numeric else "---" for i in range(len(item.headers))]
        lines = ["| " + " | ".join(escape(h) for h in item.headers) + " |",
                 "| " + " | ".join(align) + " |"]
        lines += ["| " + " | ".join(cell(c) for c in row) + " |" for row in item.rows]
        return "\n".join(lines)
    if isinstance(item, Figure):
        return figure(item) + (f"\n\n*{escape(item.caption)}*" if item.caption else "")
    if isinstance(item, Gallery):
        return f"**{escape(item.title)}**\n\n" + " ".join(figure(f) for f in item.figures)
    if isinstance(item, Preformatted):
        longest = max((len(run) for run in re.findall(r"`{3,}", item.text)), default=2)
        fence = "`" * (longest + 1)
        head = f"{escape(item.summary)}:\n\n" if item.summary else ""
        return f"{head}{fence}text\n{item.text.rstrip()}\n{fence}"
    raise TypeError(f"unknown block {item!r}")


def render(document: Document) -> str:
    """The markdown text of ``document``."""
    parts = [f"# {escape(document.title)}"] + [block(b) for b in document.blocks]
    return escape_controls("\n\n".join(parts) + "\n").replace("\r", "\\r")
