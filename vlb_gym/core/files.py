"""Reading untrusted files and writing results safely.

Every file a user or a language model names (behavior files, scripted replies, transcripts, agent
metadata) is read with :func:`read_limited`: regular files only (no FIFO, device or directory, so
``/dev/zero`` or a pipe cannot hang or exhaust the process), at most a given size. JSON documents go
through :func:`load_json`, which also caps nesting depth before the decoder recurses. Outputs are
written with :func:`write_atomic`: readers see the old file or the whole new one, and a failed write
leaves nothing behind.
"""

from __future__ import annotations

import contextlib
import json
import os
import stat
import tempfile
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from .errors import UserError

MAX_FILE_BYTES = 1_000_000
MAX_JSON_DEPTH = 64

_SHIPPED: list[Mapping[str, bytes]] = []  # the files of the innermost shipped() block


class InputFileError(UserError, ValueError):
    """An input file cannot be used; the message names the file and says why."""


@contextlib.contextmanager
def shipped(files: Mapping[str, bytes]) -> Iterator[None]:
    """Within the block, the user's input files are ``files`` (absolute resolved path ->
    bytes) and no others: :func:`read_limited`, :func:`input_bytes` and :func:`is_input_file`
    read from memory. How campaign workers read what the driver shipped, never their disk."""
    _SHIPPED.append(files)
    try:
        yield
    finally:
        _SHIPPED.pop()


def _shipped(path: str | os.PathLike[str]) -> bytes | None:
    """The shipped bytes of ``path``; InputFileError inside a :func:`shipped` block that lacks
    it, None outside any."""
    if not _SHIPPED:
        return None
    data = _SHIPPED[-1].get(str(Path(path).resolve()))
    if data is None:
        raise InputFileError(f"{named(path)}: not among the files shipped with the campaign")
    return data


def is_input_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is a regular file (inside a :func:`shipped` block: a shipped one)."""
    if _SHIPPED:
        return str(Path(path).resolve()) in _SHIPPED[-1]
    return Path(path).is_file()


def input_bytes(path: str | os.PathLike[str]) -> bytes:
    """All the bytes of an input file the user named (an agent's zip: no size limit)."""
    data = _shipped(path)
    return Path(path).read_bytes() if data is None else data


def named(path: str | os.PathLike[str]) -> str:
    """A path as an error message names it: as written, or quoted with its escapes when it
    holds a character that is not printable (a line break would split the message)."""
    text = os.fspath(path)
    return text if text.isprintable() else repr(text)


def read_limited(path: str | os.PathLike[str], limit: int = MAX_FILE_BYTES,
                 what: str = "file") -> bytes:
    """The bytes of ``path`` if it is a regular file of at most ``limit`` bytes."""
    path = Path(path)
    where = named(path)
    data = _shipped(path)
    if data is not None:
        if len(data) > limit:
            raise InputFileError(f"{where}: {what} is {len(data)} bytes; the limit is {limit}")
        return data
    try:
        # O_NONBLOCK: opening a FIFO with no writer must not block; it is refused just below
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise InputFileError(f"{where}: cannot read {what}: {exc.strerror}") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise InputFileError(f"{where}: cannot read {what}: not a regular file")
        if info.st_size > limit:
            raise InputFileError(f"{where}: {what} is {info.st_size} bytes; the limit is {limit}")
        with os.fdopen(fd, "rb", closefd=False) as handle:
            data = handle.read(limit + 1)
    finally:
        os.close(fd)
    if len(data) > limit:  # the file grew while we read it
        raise InputFileError(f"{where}: {what} is larger than the limit of {limit} bytes")
    return data


def _deeper_than(data: Any, limit: int) -> bool:
    """Whether decoded JSON nests arrays and objects more than ``limit`` deep (iterative)."""
    stack = [(data, 1)]
    while stack:
        value, depth = stack.pop()
        children = value.values() if isinstance(value, dict) else value
        if isinstance(value, (dict, list)):
            if depth > limit:
                return True
            stack.extend((child, depth + 1) for child in children)
    return False


def load_json(text: str | bytes, source: str, max_depth: int = MAX_JSON_DEPTH) -> Any:
    """Decode JSON whose nesting is at most ``max_depth``, in time linear in its length.

    Raises :class:`json.JSONDecodeError` for malformed text (so callers can report line and
    column) and :class:`InputFileError` for a document nested too deeply or holding a number
    Python refuses to convert (over 4300 digits).
    """
    try:
        data = json.loads(text)
    except json.JSONDecodeError:
        raise
    except RecursionError:  # the decoder's own recursion limit, far past max_depth
        raise InputFileError(f"{source}: JSON nested deeper than {max_depth} levels") from None
    except ValueError as exc:
        raise InputFileError(f"{source}: {exc}") from None
    if _deeper_than(data, max_depth):
        raise InputFileError(f"{source}: JSON nested deeper than {max_depth} levels")
    return data


def read_json_file(path: str | os.PathLike[str], what: str, kind: type = dict) -> Any:
    """The JSON document in ``path`` (:func:`read_limited`, :func:`load_json`), a ``kind``
    (dict or list) at the top; :class:`InputFileError` naming the file and ``what`` it should
    hold otherwise."""
    text = read_limited(path, what=what)
    try:
        data = load_json(text, str(path))
    except json.JSONDecodeError as exc:
        raise InputFileError(f"{path}: {what} is not JSON: {exc}") from None
    if not isinstance(data, kind):
        raise InputFileError(f"{path}: {what} is not a JSON "
                             f"{'object' if kind is dict else 'list'}")
    return data


class OutputFileError(UserError, OSError):
    """An output file could not be written (a full disk, a file size limit): the message names
    it."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


def write_atomic(path: str | os.PathLike[str], content: str | bytes) -> None:
    """Write ``content`` (text or bytes) to ``path`` so that readers see the old file or the whole
    new one; on any failure the temporary file is removed and the old file stays as it was. The
    file gets the permissions of a file created by ``open`` (an existing file's, if it exists)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        mode = path.stat().st_mode & 0o7777
    except FileNotFoundError:
        mode = 0o666 & ~_umask()
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, mode)  # mkstemp's file is private (0600)
        with os.fdopen(fd, "wb" if isinstance(content, bytes) else "w") as handle:
            handle.write(content)
        os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise OutputFileError(f"{path}: cannot write it ({exc.strerror or exc}); it was left as "
                              "it was") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _umask() -> int:
    """The process's umask (read by setting it, then restoring it)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask
