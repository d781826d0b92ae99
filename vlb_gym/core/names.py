"""Names of behaviors, nodes, variables and functions: one pattern, light to import (the CLI
checks ``--name`` with it before anything heavy loads)."""

from __future__ import annotations

import re

IDENTIFIER_PATTERN = r"^[A-Za-z][A-Za-z0-9_]*$"
MAX_NAME_LENGTH = 64
_NAME = re.compile(IDENTIFIER_PATTERN)


def is_name(text: str) -> bool:
    """Whether ``text`` is a name: a letter, then letters, digits and ``_``, 64 at most."""
    return len(text) <= MAX_NAME_LENGTH and _NAME.fullmatch(text) is not None
