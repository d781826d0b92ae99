"""Text from untrusted inputs made inert: every character that could drive a terminal (escape
sequences, other control characters, bidirectional overrides and invisible format characters)
written as a visible ``\\x1b``-style escape. What reaches a terminal and what is written to a
file a user may ``cat`` (report.md) goes through :func:`escape_controls`."""

from __future__ import annotations

_KEPT = {"\t", "\n", "\r"}
_FORMAT = [*range(0x200B, 0x2010), *range(0x202A, 0x202F), *range(0x2066, 0x206A), 0xFEFF]
_TABLE = {c: f"\\x{c:02x}" for c in [*range(0x20), 0x7F, *range(0x80, 0xA0)]
          if chr(c) not in _KEPT}
_TABLE.update({c: f"\\u{c:04x}" for c in _FORMAT})


def escape_controls(text: str) -> str:
    """``text`` with every control and format character but tab, newline and carriage
    return written as an escape."""
    return text.translate(_TABLE)


LONG_WORD = 160  # an echoed value longer than this is shortened in an error line
_LONG = 2000  # and an error line longer than this


def bounded(message: str) -> str:
    """``message`` with each run of more than :data:`LONG_WORD` non-blank characters (an
    echoed env id, path or value from an input) shortened to its ends and its length, and the
    whole kept to about 2,000 characters: an error line stays readable whatever it echoes."""
    def shorten(text: str, keep: int) -> str:
        return f"{text[:keep]}...[{len(text):,} characters]...{text[-keep // 2:]}"

    words = [shorten(w, 60) if len(w) > LONG_WORD else w for w in message.split(" ")]
    message = " ".join(words)
    return message if len(message) <= _LONG else shorten(message, _LONG // 2)


def single_line(message: str) -> str:
    """An error message on one line: several problems (a behavior file's) joined with "; ",
    a line break inside one (a file name's) escaped, a long echoed value shortened
    (:func:`bounded`)."""
    lines = [line.strip() for line in message.replace("\r", "\\r").split("\n")]
    return bounded("; ".join(line for line in lines if line))
