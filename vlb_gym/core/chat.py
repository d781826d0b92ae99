"""What every part of vlb-gym asks of a language model: a reply to chat messages, meeting a JSON
schema. The synthesizer's backends (:class:`vlb_gym.abstractor.backends.ChatBackend`) are chat
models that also record what they did; an env's own dialogue (the scoop's sensing-pose session)
needs no more than this."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol

Message = dict[str, str]
"""One chat message: ``{"role": ..., "content": ...}``."""


class ChatModel(Protocol):
    """A language model behind chat messages."""

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        """The model's reply to ``messages``; ``schema`` is the JSON Schema the reply must meet."""
        ...
