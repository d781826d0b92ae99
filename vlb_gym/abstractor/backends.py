"""Language-model backends for the behavior generalizer (the paper's abstractor A).

A backend turns a list of chat messages into one reply string. Three ship:

* :class:`OpenAICompatibleBackend` -- the chat-completions protocol over HTTP, as served by hosted
  APIs and by local servers (vLLM, Ollama, llama.cpp); standard library only;
* :class:`ScriptedBackend` -- canned replies, in order (tests, demos, offline use);
* :class:`TranscriptBackend` -- replays the replies recorded in a ``vlb synthesize`` transcript.
"""

from __future__ import annotations

import json
import os
import random
import socket
import time
import urllib.error
import urllib.request
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal, Protocol

Message = dict[str, str]
StructuredOutput = Literal["json_schema", "json_object", "none"]


class BackendError(RuntimeError):
    """The backend could not produce a reply (after its retries); the message says why."""


class ChatBackend(Protocol):
    """What the generalizer needs from a language model."""

    name: str

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        """The model's reply to ``messages``; ``schema`` is the JSON Schema the reply must meet."""
        ...


class OpenAICompatibleBackend:
    """Chat completions over HTTP (``POST {base_url}/chat/completions``).

    ``structured_output`` chooses what goes with the request: ``"json_schema"`` sends the
    behavior schema as ``response_format`` (OpenAI, vLLM, recent llama.cpp and Ollama),
    ``"json_object"`` asks only for JSON, ``"none"`` sends nothing (the prompt still carries the
    schema). Timeouts, connection errors, HTTP 408/409/429 and 5xx are retried ``max_retries``
    times with exponential backoff and jitter; other HTTP errors fail at once.
    """

    RETRY_STATUS = frozenset({408, 409, 429, 500, 502, 503, 504})

    def __init__(self, base_url: str, model: str, api_key_env: str = "OPENAI_API_KEY",
                 timeout: float = 60.0, max_retries: int = 3, backoff: float = 1.0,
                 structured_output: StructuredOutput = "json_schema", temperature: float = 0.0):
        if not base_url.startswith(("http://", "https://")):
            raise ValueError(f"base URL {base_url!r} must start with http:// or https://")
        if structured_output not in ("json_schema", "json_object", "none"):
            raise ValueError(f"structured_output must be json_schema, json_object or none "
                             f"(got {structured_output!r})")
        self.url = base_url.rstrip("/") + "/chat/completions"
        self.model = model
        self.api_key = os.environ.get(api_key_env) if api_key_env else None
        self.timeout, self.max_retries, self.backoff = timeout, max_retries, backoff
        self.structured_output = structured_output
        self.temperature = temperature
        self.name = f"{model} at {base_url}"

    def _body(self, messages: Sequence[Message], schema: dict[str, Any] | None) -> bytes:
        body: dict[str, Any] = {"model": self.model, "messages": list(messages),
                                "temperature": self.temperature}
        if schema is not None and self.structured_output == "json_schema":
            body["response_format"] = {"type": "json_schema", "json_schema": {
                "name": "behavior", "schema": schema, "strict": False}}
        elif self.structured_output == "json_object":
            body["response_format"] = {"type": "json_object"}
        return json.dumps(body).encode()

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        headers = {"Content-Type": "application/json", "Accept": "application/json"}
        if self.api_key:
            headers["Authorization"] = f"Bearer {self.api_key}"
        request = urllib.request.Request(self.url, self._body(messages, schema), headers)
        problems = []
        for attempt in range(self.max_retries + 1):
            if attempt:
                time.sleep(self.backoff * 2 ** (attempt - 1) * (1 + random.random() / 4))
            try:
                with urllib.request.urlopen(request, timeout=self.timeout) as response:
                    payload = response.read()
            except urllib.error.HTTPError as exc:
                detail = exc.read()[:300].decode(errors="replace")
                problems.append(f"HTTP {exc.code}: {detail}")
                if exc.code not in self.RETRY_STATUS:
                    break
                continue
            except (TimeoutError, socket.timeout) as exc:
                problems.append(f"timed out after {self.timeout:g} s ({exc})")
                continue
            except urllib.error.URLError as exc:
                if isinstance(exc.reason, (TimeoutError, socket.timeout)):
                    problems.append(f"timed out after {self.timeout:g} s")
                else:
                    problems.append(f"cannot connect: {exc.reason}")
                continue
            return self._content(payload)
        raise BackendError(f"{self.url}: no reply after {len(problems)} attempt(s); last: "
                           f"{problems[-1]}")

    def _content(self, payload: bytes) -> str:
        try:
            content = json.loads(payload)["choices"][0]["message"]["content"]
        except (ValueError, KeyError, IndexError, TypeError):
            raise BackendError(f"{self.url}: the response is not a chat completion: "
                               f"{payload[:200]!r}") from None
        if not isinstance(content, str):
            raise BackendError(f"{self.url}: the reply has no text content")
        return content


class ScriptedBackend:
    """Replies with the given strings, one per call, and records what it was asked."""

    def __init__(self, replies: Sequence[str], name: str = "scripted"):
        self.replies = list(replies)
        self.requests: list[list[Message]] = []
        self.name = name

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        self.requests.append(list(messages))
        if len(self.requests) > len(self.replies):
            raise BackendError(f"{self.name}: only {len(self.replies)} scripted repl"
                               f"{'y' if len(self.replies) == 1 else 'ies'}; asked for another")
        return self.replies[len(self.requests) - 1]

    @classmethod
    def from_file(cls, path: str | Path) -> ScriptedBackend:
        """Replies from a JSON file: a list of strings, or of behavior documents (objects)."""
        path = Path(path)
        try:
            data = json.loads(path.read_text())
        except (OSError, ValueError) as exc:
            raise BackendError(f"{path}: cannot read scripted replies: {exc}") from None
        if not isinstance(data, list) or not data:
            raise BackendError(f"{path}: expected a non-empty JSON list of replies")
        return cls([r if isinstance(r, str) else json.dumps(r, indent=2) for r in data],
                   name=f"scripted replies from {path}")


class TranscriptBackend(ScriptedBackend):
    """Replays the raw replies recorded in a ``vlb synthesize`` transcript."""

    @classmethod
    def from_file(cls, path: str | Path) -> TranscriptBackend:
        path = Path(path)
        try:
            rounds = json.loads(path.read_text())["rounds"]
            replies = [r["reply"] for r in rounds]
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise BackendError(f"{path}: not a vlb synthesize transcript: {exc}") from None
        return cls(replies, name=f"transcript {path}")
