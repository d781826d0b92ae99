"""The report as renderer-neutral blocks, so that report.md and report.html say the same thing.

Text in blocks is plain, untrusted text (behavior names, reasons and causes come from files and
episodes); each renderer escapes it for its own format.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


def short(text: Any, limit: int) -> str:
    """``text`` on one line (runs of white space made one space), cut to ``limit`` characters."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[:limit - 1] + "…"


@dataclass(frozen=True)
class Code:
    """Inline code (a command, a seed, a digest)."""

    text: str


@dataclass(frozen=True)
class Strong:
    """Inline emphasis."""

    text: str


Inline = str | Code | Strong
Cell = Inline | list[Inline]


@dataclass(frozen=True)
class Heading:
    level: int
    text: str


@dataclass(frozen=True)
class Paragraph:
    parts: list[Inline]


@dataclass(frozen=True)
class Table:
    headers: list[str]
    rows: list[list[Cell]]
    numeric: tuple[int, ...] = ()  # columns aligned right


@dataclass(frozen=True)
class Figure:
    """A PNG picture: ``name`` is its file name next to report.md; html embeds ``png``."""

    name: str
    png: bytes
    alt: str
    caption: str = ""


@dataclass(frozen=True)
class Gallery:
    """A row of small pictures (frames of one episode)."""

    title: str
    figures: list[Figure]


@dataclass(frozen=True)
class Preformatted:
    """Verbatim text (tracebacks); ``summary`` is a one-line label shown before it."""

    text: str
    summary: str = ""


Block = Heading | Paragraph | Table | Figure | Gallery | Preformatted


@dataclass
class Document:
    title: str
    blocks: list[Block] = field(default_factory=list)

    def add(self, *blocks: Block) -> None:
        self.blocks.extend(blocks)

    def figures(self) -> list[Figure]:
        """Every picture, in order (gallery pictures included)."""
        found: list[Figure] = []
        for block in self.blocks:
            if isinstance(block, Figure):
                found.append(block)
            elif isinstance(block, Gallery):
                found.extend(block.figures)
        return found
