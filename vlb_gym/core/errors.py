"""The base of every error vlb-gym raises about what a user gave it.

A :class:`UserError` is about the input, not the package: a behavior file or expression that
does not check, an unusable input or output file, a store that does not match, an env or
cluster that cannot be set up, a language model that does not answer usefully, a bad command
line. The command line prints one as one line and exits with 2; a library caller catches
``UserError`` for all of them. Each subclass also derives from the builtin it refines
(``ValueError``, ``OSError``, ``RuntimeError``), so code catching those keeps working.
"""

from __future__ import annotations


class UserError(Exception):
    """An error in what the user gave vlb-gym (see the module's docstring)."""
