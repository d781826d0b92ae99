"""The structured-output dialects of chat-completion servers and how to read their replies:
which request shape each dialect sends, which error says a server rejects a shape, what a probe
reply must be, and the limits a reply is held to."""

from __future__ import annotations

import json
from typing import Any, Literal

from vlb_gym.core.files import load_json

from .backends import Message

StructuredOutput = Literal["auto", "openai", "json_schema", "vllm", "ollama", "llamacpp",
                           "json_object", "none"]

DIALECTS: dict[str, str] = {
    "openai": "response_format json_schema",
    "llamacpp": "json_object + schema",
    "vllm": "guided_json",
    "ollama": "native /api/chat, format: schema",
    "json_object": "JSON mode, no schema",
    "none": "no constraint"}
"""The request shapes of structured output, each with what it sends:

* ``openai``: ``response_format: {"type": "json_schema", "json_schema": {"name", "schema",
  "strict": false}}`` (OpenAI; vLLM's OpenAI server; recent llama.cpp and Ollama ``/v1``);
* ``llamacpp``: ``response_format: {"type": "json_object", "schema": SCHEMA}`` (llama.cpp's
  server and llama-cpp-python's server, which answer ``json_schema`` with an error);
* ``vllm``: ``guided_json: SCHEMA`` in the body (vLLM's extra parameter, older versions too);
* ``ollama``: Ollama's native ``POST {origin}/api/chat`` with ``format: SCHEMA`` (its ``/v1``
  endpoint took no schema before version 0.5); a base URL ending in ``/v1`` loses it there;
* ``json_object``: ``response_format: {"type": "json_object"}``, JSON without a schema;
* ``none``: nothing (the prompt still carries the schema).
"""
AUTO_ORDER: tuple[str, ...] = ("openai", "llamacpp", "vllm", "ollama", "json_object", "none")
"""The order in which ``structured_output="auto"`` probes the dialects (see
:meth:`OpenAICompatibleBackend.probe`)."""
ALIASES = {"json_schema": "openai"}
"""Older names of dialects, still accepted."""

PROBE_SCHEMA: dict[str, Any] = {
    "type": "object",
    "properties": {"ok": {"type": "boolean"}, "probe": {"enum": ["vlb"]}},
    "required": ["ok", "probe"], "additionalProperties": False}
"""The probe's schema. The probe asks for ``{"ok": true}`` only: a server that enforces the
schema makes the model add ``"probe": "vlb"``; a server that ignores it gets ``{"ok": true}``
(or free text) from an obliging model, which does not match, so the next dialect is tried."""
PROBE_MESSAGES: list[Message] = [{"role": "user", "content": (
    'This is a connection test. Reply with the JSON object {"ok": true} and nothing else.')}]
PROBE_MAX_TOKENS = 256
"""Tokens the probe allows: room for a reasoning model's thoughts before ``{"ok": true}``."""
MISSING_ENDPOINT = (404, 405)
"""Statuses that say the OpenAI-compatible ``/chat/completions`` is not there (Ollama without
``/v1``): the probe then tries only the dialects with an endpoint of their own."""
OLLAMA_NUM_CTX = 8192
"""Context window asked of Ollama (its default, 2,048 or 4,096 tokens, would silently cut the
behavior prompt)."""

MAX_REPLY_BYTES = 2_000_000
"""Default cap on the body of one HTTP reply; a larger reply fails (and is not read further)."""
MAX_REPLY_CHARS = 100_000
"""Default cap on the reply text returned (and so kept in transcripts); the rest is cut off."""
MAX_DETAIL_CHARS = 300
"""How much of a server's error message goes into a :class:`ModelError`."""
VALIDATION_MARKERS = ("validation", "literal_error", "input should be", "'loc'", '"loc"',
                      "response_format")
"""Text that marks an HTTP 500 body as a request-validation error (see :func:`request_rejected`)."""


def request_rejected(status: int, body: str) -> bool:
    """Whether an HTTP error status (with its body) says the request itself is wrong, so that
    sending it again cannot help.

    Client errors (4xx) do, except 408 (request timeout), 409 (conflict) and 429 (rate limit).
    So does an HTTP 500 whose body reads as a request-validation error: llama-cpp-python's
    server, for one, answers a ``response_format`` it does not support with ``500`` and a
    pydantic error list (``'type': 'literal_error', 'loc': ('body', 'response_format', 'type'),
    'msg': "Input should be 'text' or 'json_object'"``); any of :data:`VALIDATION_MARKERS`
    (case-insensitive) counts. Every other 5xx may pass and is worth retrying.
    """
    if 400 <= status < 500:
        return status not in (408, 409, 429)
    return status == 500 and any(marker in body.lower() for marker in VALIDATION_MARKERS)


def shape_rejected(status: int, body: str, dialect: str) -> bool:
    """Whether an HTTP error answering a probe in ``dialect`` is a clear rejection of that
    request shape, so that :meth:`OpenAICompatibleBackend.probe` moves on to the next dialect:
    HTTP 400 or 422, an HTTP 500 that reads as a request-validation error (see
    :func:`request_rejected`; llama-cpp-python's answer to ``json_schema``), and for ``ollama``
    also 404, 405 and a 200 that is not an Ollama reply (no native endpoint there). Other errors (401, 403, 404, 429, 5xx, ...) say
    nothing about the shape and end the probe."""
    if status in (400, 422):
        return True
    if dialect == "ollama" and status in (200, 404, 405):
        return True  # no native endpoint there (a 200 that is no Ollama reply: see _content)
    return status == 500 and request_rejected(status, body)


def probe_reply_ok(reply: str, dialect: str) -> bool:
    """Whether the reply to a probe shows that ``dialect`` was honoured: for ``json_object`` a
    JSON object, for the schema dialects a document of :data:`PROBE_SCHEMA` exactly, for
    ``none`` anything."""
    if dialect == "none":
        return True
    try:
        data = json.loads(reply)
    except ValueError:
        return False
    if not isinstance(data, dict):
        return False
    if dialect == "json_object":
        return True
    return (set(data) == {"ok", "probe"} and isinstance(data["ok"], bool)
            and data["probe"] == "vlb")


def dialect_label(dialect: str) -> str:
    """``dialect (what it sends)``, e.g. ``llamacpp (json_object + schema)``."""
    return f"{dialect} ({DIALECTS[dialect]})"


def server_message(body: str) -> str:
    """What an error reply says, on one line and at most :data:`MAX_DETAIL_CHARS` characters:
    the ``error.message`` (or ``error``) of an OpenAI-style JSON body, else the body itself."""
    try:
        data = load_json(body, "error reply")
    except ValueError:
        data = None
    error = data.get("error") if isinstance(data, dict) else None
    if isinstance(error, dict) and isinstance(error.get("message"), str):
        body = error["message"]
    elif isinstance(error, str):
        body = error
    line = " ".join(body.split())
    return line if len(line) <= MAX_DETAIL_CHARS else line[:MAX_DETAIL_CHARS] + "..."
