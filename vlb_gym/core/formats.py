"""Format versions of the files users keep: behavior files, stores, report.json, exports.

Each kind has one current format (:data:`CURRENT`), written into every file of that kind this
package writes (a behavior file's ``"format"``, a store's SQLite ``user_version``, report.json's
``"format"``, an export's plan line). Readers accept the current format and every earlier one;
a file without a version was written before formats were versioned and is format 1. A file of a
later format (a newer vlb-gym wrote it) is refused in one line, never misread. CHANGELOG.md says
what each format change means for users' files; ``tests/fixtures/formats`` holds a file of each
kind and format, which the suite reads with today's readers.
"""

from __future__ import annotations

from typing import Any

from .errors import UserError

CURRENT = {"behavior": 1, "store": 2, "report": 1, "export": 2}
"""The format each kind of file is written in."""

WHAT = {"behavior": "behavior file", "store": "store", "report": "report", "export": "export"}


class FormatError(UserError, ValueError):
    """A file's format version is not one this vlb-gym reads."""


def check_format(kind: str, found: Any, where: str) -> int:
    """The format of a ``kind`` file that says ``found`` (None: written before formats were
    versioned, format 1); FormatError naming ``where`` if it is no format this package reads."""
    if found is None:
        return 1
    current = CURRENT[kind]
    if type(found) is not int or found < 1:
        raise FormatError(f"{where}: the {WHAT[kind]} format must be a positive integer (got "
                          f"{str(found)[:40]!r})")
    if found > current:
        from vlb_gym import __version__

        raise FormatError(f"{where}: {WHAT[kind]} format {found} was written by a newer vlb-gym; "
                          f"this one ({__version__}) reads formats 1 to {current}: upgrade "
                          "vlb-gym to read it")
    return found
