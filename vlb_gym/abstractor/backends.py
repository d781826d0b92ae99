"""Language-model backends for the behavior generalizer (the paper's abstractor A).

A backend turns a list of chat messages into one reply string (:class:`ChatBackend`). Besides
the served models of :mod:`.served` and the local ones of :mod:`.local`:

* :class:`ScriptedBackend` -- canned replies, in order (tests, demos, offline use);
* :class:`TranscriptBackend` -- replays the replies recorded in a ``vlb synthesize`` transcript.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Protocol

from vlb_gym.core.chat import ChatModel, Message
from vlb_gym.core.errors import UserError
from vlb_gym.core.files import InputFileError, load_json, read_limited


class ModelError(UserError, RuntimeError):
    """The language model's backend could not produce a reply (after its retries); the message
    says why. (A backend that runs episodes fails with
    :class:`vlb_gym.verify.backends.BackendError`.)

    ``status`` and ``body`` are the HTTP status and body of the last reply when that was an HTTP
    error (else None and ``""``)."""

    def __init__(self, message: str, status: int | None = None, body: str = ""):
        super().__init__(message)
        self.status, self.body = status, body


class ChatBackend(ChatModel, Protocol):
    """A :class:`~vlb_gym.core.chat.ChatModel` as the generalizer uses it, and what it records of
    one: ``usage``,
    one entry per draw where the backend measures them (a local model: tokens and seconds),
    else empty; ``dialect``, the structured-output dialect a served model used (None elsewhere
    or before it probed); ``probe_log``, what each probe of ``"auto"`` got."""

    name: str
    usage: list[dict[str, Any]]
    probe_log: list[dict[str, str]]

    @property
    def dialect(self) -> str | None: ...


RESAMPLES = 2
"""Draws after the first when a reply repeats an earlier assistant turn."""
RESAMPLE_TEMPERATURE = 0.7
"""The least temperature of those draws: greedy decoding would repeat the same reply."""


def unrepeated(draw: Callable[[float, int | None], str], messages: Sequence[Message],
               temperature: float, seed: int | None) -> str:
    """``draw(temperature, seed)``, drawn again while the reply repeats an earlier assistant
    turn of ``messages`` (a rejected reply the conversation kept, or a worked example copied):
    at least at :data:`RESAMPLE_TEMPERATURE` with another seed, up to :data:`RESAMPLES` times.
    The redraw policy of every model backend."""
    earlier = {m["content"] for m in messages if m["role"] == "assistant"}
    reply = draw(temperature, seed)
    for n in range(1, RESAMPLES + 1):
        if reply not in earlier:
            break
        reply = draw(max(temperature, RESAMPLE_TEMPERATURE), (seed or 0) + n)
    return reply


class ScriptedBackend:
    """Replies with the given strings, one per call, and records what it was asked; a None
    reply (a recorded backend failure) is that failure again."""

    dialect = None

    def __init__(self, replies: Sequence[str | None], name: str = "scripted"):
        self.replies = list(replies)
        self.requests: list[list[Message]] = []
        self.name = name
        self.usage: list[dict[str, Any]] = []
        self.probe_log: list[dict[str, str]] = []

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        self.requests.append(list(messages))
        if len(self.requests) > len(self.replies):
            raise ModelError(f"{self.name}: only {len(self.replies)} scripted repl"
                               f"{'y' if len(self.replies) == 1 else 'ies'}; asked for another")
        reply = self.replies[len(self.requests) - 1]
        if not isinstance(reply, str):
            raise ModelError(f"{self.name}: reply {len(self.requests)} was recorded as a "
                               "failure of the language model, not a reply")
        return reply

    @classmethod
    def from_file(cls, path: str | Path) -> ScriptedBackend:
        """Replies from a JSON file: a list of strings, or of behavior documents (objects)."""
        data = _load_file(path, "scripted replies")
        if not isinstance(data, list) or not data:
            raise ModelError(f"{path}: expected a non-empty JSON list of replies")
        return cls([r if isinstance(r, str) else json.dumps(r, indent=2) for r in data],
                   name=f"scripted replies from {path}")


class TranscriptBackend(ScriptedBackend):
    """Replays the raw replies recorded in a ``vlb synthesize`` transcript (a graph-first one's
    ``rounds``, or an intent-first one's ``drafts``: each draft's rounds, then those of its
    witnessed redraft, in the order they were asked)."""

    @classmethod
    def from_file(cls, path: str | Path) -> TranscriptBackend:
        data = _load_file(path, "transcript")
        try:
            rounds = ([r for d in data["drafts"]
                       for r in d["rounds"] + (d["witnessed"]["rounds"] if "witnessed" in d
                                               else [])]
                      if isinstance(data, dict) and "drafts" in data else data["rounds"])
            replies = [r["reply"] for r in rounds]
            if not all(r is None or isinstance(r, str) for r in replies):
                raise TypeError
        except (KeyError, TypeError):
            raise ModelError(f"{path}: not a vlb synthesize transcript (expected an object "
                               f"with a list of rounds, each with a reply)") from None
        return cls(replies, name=f"transcript {path}")


def _load_file(path: str | Path, what: str) -> Any:
    """The JSON document in ``path``, read with the limits of :mod:`vlb_gym.core.files` (a
    regular file, bounded size and nesting); any problem is a one-line :class:`ModelError`
    naming the file."""
    try:
        return load_json(read_limited(path, what=what), str(path))
    except InputFileError as exc:  # its message names the file
        raise ModelError(str(exc)) from None
    except OSError as exc:  # read_limited lets a few through (a directory, for one)
        raise ModelError(f"{path}: cannot read {what}: {exc.strerror}") from None
    except ValueError as exc:
        raise ModelError(f"{path}: {what} is not valid JSON: {exc}") from None
