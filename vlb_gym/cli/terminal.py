"""What reaches the terminal: everything ``vlb`` prints goes through :func:`neutral`, so that
text from its inputs (a store's reasons, a behavior's names, a model's reply, a server's error
body) can never drive the terminal: escape sequences (clear the screen, set the title, write
the clipboard with OSC 52), other control characters and bidirectional overrides are shown as
``\\x1b``-style escapes instead. Tabs and newlines pass, and a carriage return that starts a
write (a progress bar redrawing its line); summaries put each line from an input on one line
themselves (:func:`~vlb_gym.verify.report.one_line`)."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator
from typing import Any, TextIO

from vlb_gym.core.text import escape_controls



def neutral(text: str) -> str:
    """``text`` with every character that could drive a terminal written as an escape; a
    carriage return only at its start (a progress bar redrawing its line), else escaped."""
    head = "\r" if text.startswith("\r") else ""
    return head + escape_controls(text[len(head):]).replace("\r", "\\r")


class NeutralStream:
    """A text stream that writes through :func:`neutral` to ``inner``."""

    def __init__(self, inner: TextIO):
        self.inner = inner

    def write(self, text: str) -> int:
        self.inner.write(neutral(text))
        return len(text)

    def __getattr__(self, name: str) -> Any:  # flush, isatty, fileno, encoding, ...
        return getattr(self.inner, name)


@contextlib.contextmanager
def neutral_output() -> Iterator[None]:
    """Standard output and error through :func:`neutral` while the block runs."""
    saved = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = NeutralStream(sys.stdout), NeutralStream(sys.stderr)
    try:
        yield
    finally:
        sys.stdout, sys.stderr = saved
