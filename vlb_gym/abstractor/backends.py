"""Language-model backends for the behavior generalizer (the paper's abstractor A).

A backend turns a list of chat messages into one reply string. Three ship:

* :class:`OpenAICompatibleBackend` -- the chat-completions protocol over HTTP (httpx), as served by
  hosted APIs and by local servers (vLLM, Ollama, llama.cpp); it treats the server as untrusted:
  no redirect is followed (the API key goes to the configured origin only), each attempt has a
  total deadline, replies are size-capped, and requests the server rejects are not sent again;
* :class:`ScriptedBackend` -- canned replies, in order (tests, demos, offline use);
* :class:`TranscriptBackend` -- replays the replies recorded in a ``vlb synthesize`` transcript.
"""

from __future__ import annotations

import json
import os
import random
import socket
import threading
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, Literal, Protocol

import httpx

from vlb_gym.core.files import InputFileError, load_json, read_limited

Message = dict[str, str]
StructuredOutput = Literal["json_schema", "json_object", "none"]

MAX_REPLY_BYTES = 2_000_000
"""Default cap on the body of one HTTP reply; a larger reply fails (and is not read further)."""
MAX_REPLY_CHARS = 100_000
"""Default cap on the reply text returned (and so kept in transcripts); the rest is cut off."""
MAX_DETAIL_CHARS = 300
"""How much of a server's error message goes into a :class:`BackendError`."""
VALIDATION_MARKERS = ("validation", "literal_error", "input should be", "'loc'", '"loc"',
                      "response_format")
"""Text that marks an HTTP 500 body as a request-validation error (see :func:`request_rejected`)."""


class BackendError(RuntimeError):
    """The backend could not produce a reply (after its retries); the message says why."""


class ChatBackend(Protocol):
    """What the generalizer needs from a language model."""

    name: str

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        """The model's reply to ``messages``; ``schema`` is the JSON Schema the reply must meet."""
        ...


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


class _Failure(Exception):
    """One attempt failed; ``retry`` says whether another attempt might succeed."""

    def __init__(self, problem: str, retry: bool):
        super().__init__(problem)
        self.problem, self.retry = problem, retry


class _Deadline:
    """A total deadline for one HTTP attempt, ``seconds`` from when it is entered.

    httpx's timeouts bound each socket wait, not the whole exchange: a server sending a byte a
    second would never trip them. So the connection's socket, learnt from httpcore's ``trace``
    request extension, is shut down when the deadline passes; that ends any read or write blocked
    on it, in the headers or the body alike, and ``expired`` then tells why the exchange broke.
    """

    def __init__(self, seconds: float):
        self.expired = False
        self._socket: socket.socket | None = None
        self._lock = threading.Lock()
        self._timer = threading.Timer(seconds, self._expire)
        self._timer.daemon = True

    def __enter__(self) -> _Deadline:
        self._timer.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._timer.cancel()

    def trace(self, event: str, info: dict[str, Any]) -> None:
        """httpcore's ``trace`` callback: note the socket once connected (or wrapped in TLS)."""
        if event.endswith(("connect_tcp.complete", "start_tls.complete")):
            sock = info["return_value"].get_extra_info("socket")
            with self._lock:
                self._socket = sock if isinstance(sock, socket.socket) else None
            if self.expired:
                self._shut()

    def _expire(self) -> None:
        self.expired = True
        self._shut()

    def _shut(self) -> None:
        with self._lock:
            if self._socket is not None:
                try:
                    self._socket.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass  # closed already: the exchange is over


class OpenAICompatibleBackend:
    """Chat completions over HTTP (``POST {base_url}/chat/completions``), with httpx.

    ``structured_output`` chooses what goes with the request: ``"json_schema"`` sends the
    behavior schema as ``response_format`` (OpenAI, vLLM, recent llama.cpp and Ollama),
    ``"json_object"`` asks only for JSON, ``"none"`` sends nothing (the prompt still carries the
    schema). The API key is read from the environment variable ``api_key_env``; it is never part
    of an error message or of ``name``, and a base URL with credentials in it is refused.

    What the server can and cannot do to the client:

    * redirects are not followed: a 3xx fails at once, naming where it pointed, so the request
      and its key reach only ``base_url``'s origin;
    * ``timeout`` is a total deadline for each attempt -- connect, send, wait and the whole
      body -- however slowly the server trickles bytes;
    * a reply body over ``max_reply_bytes`` fails (not retried; reading stops there), and the
      reply text returned is cut to ``max_reply_chars``;
    * timeouts, connection errors, HTTP 408/409/429 and 5xx are retried ``max_retries`` times
      with exponential backoff (``backoff`` seconds, doubling) and jitter; a request the server
      rejects as malformed (see :func:`request_rejected`) fails at once with its message.

    Environment proxy settings (``HTTPS_PROXY`` and the like) apply, as users expect.
    """

    def __init__(self, base_url: str, model: str, api_key_env: str = "OPENAI_API_KEY",
                 timeout: float = 60.0, max_retries: int = 3, backoff: float = 1.0,
                 structured_output: StructuredOutput = "json_schema", temperature: float = 0.0,
                 max_reply_bytes: int = MAX_REPLY_BYTES, max_reply_chars: int = MAX_REPLY_CHARS):
        try:
            url = httpx.URL(base_url)
        except httpx.InvalidURL as exc:
            raise ValueError(f"base URL {base_url!r} is not a valid URL: {exc}") from None
        if url.scheme not in ("http", "https") or not url.host:
            raise ValueError(f"base URL {base_url!r} must start with http:// or https:// and "
                             f"name a host")
        if url.userinfo:
            raise ValueError("the base URL must not carry credentials (user:password@); the API "
                             "key comes from the environment variable named by api_key_env")
        if structured_output not in ("json_schema", "json_object", "none"):
            raise ValueError(f"structured_output must be json_schema, json_object or none "
                             f"(got {structured_output!r})")
        if timeout <= 0 or max_retries < 0 or max_reply_bytes < 1 or max_reply_chars < 1:
            raise ValueError("timeout and the reply limits must be positive, max_retries at "
                             "least 0")
        self.url = base_url.rstrip("/") + "/chat/completions"
        self.model = model
        self.api_key = os.environ.get(api_key_env) if api_key_env else None
        self.timeout, self.max_retries, self.backoff = timeout, max_retries, backoff
        self.structured_output = structured_output
        self.temperature = temperature
        self.max_reply_bytes, self.max_reply_chars = max_reply_bytes, max_reply_chars
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
        body = self._body(messages, schema)
        problems = []
        for attempt in range(self.max_retries + 1):
            if attempt:
                time.sleep(self.backoff * 2 ** (attempt - 1) * (1 + random.random() / 4))
            try:
                return self._attempt(body)
            except _Failure as failure:
                problems.append(failure.problem)
                if not failure.retry:
                    break
        problem = problems[-1].replace(self.api_key, "[API key]") if self.api_key \
            else problems[-1]
        if len(problems) == 1:
            raise BackendError(f"{self.url}: {problem}")
        raise BackendError(f"{self.url}: no reply after {len(problems)} attempt(s); last: "
                           f"{problem}")

    def _attempt(self, body: bytes) -> str:
        """One request; raises :class:`_Failure` saying what went wrong and if a retry may help."""
        headers = {"Content-Type": "application/json", "Accept": "application/json",
                   "Accept-Encoding": "identity"}  # the size cap counts the bytes as sent
        if self.api_key:
            headers["Authorization"] = f"Bearer {self.api_key}"
        timed_out = _Failure(f"timed out after {self.timeout:g} s", retry=True)
        # A client per attempt, so that each attempt opens a connection whose socket the deadline
        # learns; httpx's own per-phase timeout bounds connecting before there is a socket.
        deadline = _Deadline(self.timeout)
        try:
            with httpx.Client(follow_redirects=False, timeout=self.timeout) as client, deadline, \
                    client.stream("POST", self.url, content=body, headers=headers,
                                  extensions={"trace": deadline.trace}) as response:
                if 300 <= response.status_code < 400:
                    raise _Failure(self._redirect_problem(response), retry=False)
                encoding = response.headers.get("Content-Encoding", "identity").lower()
                if encoding != "identity":
                    raise _Failure(f"the reply is compressed ({encoding}) though it was asked "
                                   f"not to be", retry=False)
                payload = bytearray()
                for chunk in response.iter_raw():
                    payload += chunk
                    if deadline.expired or len(payload) > self.max_reply_bytes:
                        break
        except httpx.TimeoutException:
            raise timed_out from None
        except httpx.TransportError as exc:
            if deadline.expired:
                raise timed_out from None
            verb = "cannot connect" if isinstance(exc, httpx.ConnectError) else "connection failed"
            raise _Failure(f"{verb}: {str(exc) or type(exc).__name__}", retry=True) from None
        if deadline.expired:  # the socket was shut: what came may be cut short
            raise timed_out
        if len(payload) > self.max_reply_bytes:
            raise _Failure(f"the reply is larger than the limit of {self.max_reply_bytes} bytes",
                           retry=False)
        if not response.is_success:
            text = payload.decode(errors="replace")
            raise _Failure(f"HTTP {response.status_code}: {server_message(text)}",
                           retry=not request_rejected(response.status_code, text))
        return self._content(bytes(payload))

    def _redirect_problem(self, response: httpx.Response) -> str:
        location = response.headers.get("Location")
        try:
            target = response.request.url.join(location) if location else None
        except httpx.InvalidURL:
            target = None
        where = f"to {target.scheme}://{target.netloc.decode()}" if target else "elsewhere"
        return (f"HTTP {response.status_code} redirect {where} not followed (requests and the "
                f"API key go only to the base URL's origin); use the final address as base URL")

    def _content(self, payload: bytes) -> str:
        try:
            content = load_json(payload, self.url)["choices"][0]["message"]["content"]
        except (ValueError, KeyError, IndexError, TypeError):
            raise _Failure(f"the response is not a chat completion: {payload[:200]!r}",
                           retry=False) from None
        if not isinstance(content, str):
            raise _Failure("the reply has no text content", retry=False)
        if len(content) > self.max_reply_chars:
            content = (content[:self.max_reply_chars] + f"\n[... cut: the reply has "
                       f"{len(content)} characters; at most {self.max_reply_chars} are kept]")
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
        data = _load_file(path, "scripted replies")
        if not isinstance(data, list) or not data:
            raise BackendError(f"{path}: expected a non-empty JSON list of replies")
        return cls([r if isinstance(r, str) else json.dumps(r, indent=2) for r in data],
                   name=f"scripted replies from {path}")


class TranscriptBackend(ScriptedBackend):
    """Replays the raw replies recorded in a ``vlb synthesize`` transcript."""

    @classmethod
    def from_file(cls, path: str | Path) -> TranscriptBackend:
        data = _load_file(path, "transcript")
        try:
            replies = [r["reply"] for r in data["rounds"]]
        except (KeyError, TypeError):
            raise BackendError(f"{path}: not a vlb synthesize transcript (expected an object "
                               f"with a list of rounds, each with a reply)") from None
        return cls(replies, name=f"transcript {path}")


def _load_file(path: str | Path, what: str) -> Any:
    """The JSON document in ``path``, read with the limits of :mod:`vlb_gym.core.files` (a
    regular file, bounded size and nesting); any problem is a one-line :class:`BackendError`
    naming the file."""
    try:
        return load_json(read_limited(path, what=what), str(path))
    except InputFileError as exc:  # its message names the file
        raise BackendError(str(exc)) from None
    except OSError as exc:  # read_limited lets a few through (a directory, for one)
        raise BackendError(f"{path}: cannot read {what}: {exc.strerror}") from None
    except ValueError as exc:
        raise BackendError(f"{path}: {what} is not valid JSON: {exc}") from None
