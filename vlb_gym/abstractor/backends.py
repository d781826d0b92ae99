"""Language-model backends for the behavior generalizer (the paper's abstractor A).

A backend turns a list of chat messages into one reply string. Three ship:

* :class:`OpenAICompatibleBackend` -- the chat-completions protocol over HTTP (httpx), as served by
  hosted APIs and by local servers (vLLM, Ollama, llama.cpp), with structured output in each
  server's dialect (:data:`DIALECTS`, or ``"auto"``: probed once); it treats the server as untrusted:
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
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Literal, Protocol

import httpx

from vlb_gym.core.files import InputFileError, load_json, read_limited

Message = dict[str, str]
Dialect = Literal["openai", "vllm", "ollama", "llamacpp", "json_object", "none"]
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
"""How much of a server's error message goes into a :class:`BackendError`."""
VALIDATION_MARKERS = ("validation", "literal_error", "input should be", "'loc'", '"loc"',
                      "response_format")
"""Text that marks an HTTP 500 body as a request-validation error (see :func:`request_rejected`)."""


class BackendError(RuntimeError):
    """The backend could not produce a reply (after its retries); the message says why.

    ``status`` and ``body`` are the HTTP status and body of the last reply when that was an HTTP
    error (else None and ``""``)."""

    def __init__(self, message: str, status: int | None = None, body: str = ""):
        super().__init__(message)
        self.status, self.body = status, body


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


class _Failure(Exception):
    """One attempt failed; ``retry`` says whether another attempt might succeed."""

    def __init__(self, problem: str, retry: bool, status: int | None = None, body: str = ""):
        super().__init__(problem)
        self.problem, self.retry = problem, retry
        self.status, self.body = status, body


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

    ``structured_output`` is the dialect of structured output (see :data:`DIALECTS`; the
    ``ollama`` dialect talks to Ollama's native ``/api/chat`` instead), ``"json_schema"`` being
    an alias of ``"openai"``; ``"auto"`` finds it with :meth:`probe` before the first request and
    keeps it (``dialect``; ``probe_log`` says what each probe got). The API key is read from the
    environment variable ``api_key_env``; it is never part of an error message or of ``name``,
    and a base URL with credentials in it is refused.

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
                 structured_output: StructuredOutput = "openai", temperature: float = 0.0,
                 max_reply_bytes: int = MAX_REPLY_BYTES, max_reply_chars: int = MAX_REPLY_CHARS,
                 max_tokens: int | None = None, seed: int | None = None):
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
        structured_output = ALIASES.get(structured_output, structured_output)
        if structured_output != "auto" and structured_output not in DIALECTS:
            raise ValueError(f"structured_output must be auto, {', '.join(DIALECTS)} or "
                             f"json_schema (got {structured_output!r})")
        if timeout <= 0 or max_retries < 0 or max_reply_bytes < 1 or max_reply_chars < 1 \
                or (max_tokens is not None and max_tokens < 1) or temperature < 0:
            raise ValueError("timeout, max_tokens and the reply limits must be positive, "
                             "max_retries and temperature at least 0")
        base = base_url.rstrip("/")
        self.url = base + "/chat/completions"
        self.native_url = base.removesuffix("/v1") + "/api/chat"
        self.model = model
        self.api_key = os.environ.get(api_key_env) if api_key_env else None
        self.timeout, self.max_retries, self.backoff = timeout, max_retries, backoff
        self.structured_output = structured_output
        self.probe_log: list[dict[str, str]] = []
        self._dialect = None if structured_output == "auto" else structured_output
        self.temperature, self.seed, self.max_tokens = temperature, seed, max_tokens
        self.max_reply_bytes, self.max_reply_chars = max_reply_bytes, max_reply_chars
        self.name = f"{model} at {base_url}"

    @property
    def dialect(self) -> str | None:
        """The dialect in use; None while ``"auto"`` has not probed yet."""
        return self._dialect

    def _body(self, dialect: str, messages: Sequence[Message], schema: dict[str, Any] | None,
              max_tokens: int | None = None, strict: bool = False, temperature: float = 0.0,
              seed: int | None = None) -> bytes:
        if dialect == "ollama":
            options: dict[str, Any] = {"temperature": temperature, "num_ctx": OLLAMA_NUM_CTX}
            if max_tokens is not None:
                options["num_predict"] = max_tokens
            if seed is not None:
                options["seed"] = seed
            body: dict[str, Any] = {"model": self.model, "messages": list(messages),
                                    "stream": False, "options": options}
            if schema is not None:
                body["format"] = schema
            return json.dumps(body).encode()
        body = {"model": self.model, "messages": list(messages), "temperature": temperature}
        if max_tokens is not None:
            body["max_tokens"] = max_tokens
        if seed is not None:
            body["seed"] = seed
        if dialect == "openai" and schema is not None:
            body["response_format"] = {"type": "json_schema", "json_schema": {
                "name": "behavior" if not strict else "probe", "schema": schema,
                "strict": strict}}
        elif dialect == "llamacpp":
            body["response_format"] = {"type": "json_object"}
            if schema is not None:
                body["response_format"]["schema"] = schema
        elif dialect == "vllm" and schema is not None:
            body["guided_json"] = schema
        elif dialect == "json_object":
            body["response_format"] = {"type": "json_object"}
        return json.dumps(body).encode()

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        """One reply, with the backend's temperature, seed and token limit; a reply that repeats
        an earlier assistant turn is drawn again (:func:`unrepeated`)."""
        dialect = self.probe()

        def draw(temperature: float, seed: int | None) -> str:
            return self._request(dialect, self._body(dialect, messages, schema, self.max_tokens,
                                                     temperature=temperature, seed=seed))

        return unrepeated(draw, messages, self.temperature, self.seed)

    def probe(self) -> str:
        """The dialect to use; for ``"auto"``, found once (then kept) by sending a tiny request
        (:data:`PROBE_MESSAGES`, at most :data:`PROBE_MAX_TOKENS` tokens, :data:`PROBE_SCHEMA`)
        in each dialect of :data:`AUTO_ORDER` until one is honoured.

        A dialect is passed over when the server clearly rejects its shape (see
        :func:`shape_rejected`; such a request is never sent again) or answers with a reply that
        shows it was ignored (see :func:`probe_reply_ok`): vLLM, for one, ignores fields it does
        not know. Any other failure -- a timeout, a refused connection, HTTP 401 -- is a
        :class:`BackendError` naming the dialect being probed, not a reason to fall back.
        """
        if self._dialect is not None:
            return self._dialect
        missing = False  # no /chat/completions: only the native dialect can answer
        for dialect in AUTO_ORDER:
            if missing and dialect != "ollama":
                continue
            strict = dialect == "openai"  # the probe schema is strict-ready: OpenAI enforces it
            body = self._body(dialect, PROBE_MESSAGES, PROBE_SCHEMA, PROBE_MAX_TOKENS, strict)
            try:
                reply = self._request(dialect, body)
            except BackendError as exc:
                if exc.status in MISSING_ENDPOINT and dialect != "ollama":
                    missing = True
                    self.probe_log.append({"dialect": dialect, "outcome": f"no endpoint: {exc}"})
                    continue
                if exc.status is not None and shape_rejected(exc.status, exc.body, dialect):
                    self.probe_log.append({"dialect": dialect, "outcome": f"rejected: {exc}"})
                    continue
                raise BackendError(f"structured output probe ({dialect}): {exc}", exc.status,
                                   exc.body) from None
            if not reply.strip():
                raise BackendError(f"structured output probe ({dialect}): the model replied "
                                   f"nothing within {PROBE_MAX_TOKENS} tokens (a reasoning model "
                                   "may spend them thinking); name the dialect with "
                                   "--structured-output instead of auto")
            if probe_reply_ok(reply, dialect):
                self.probe_log.append({"dialect": dialect, "outcome": "used"})
                self._dialect = dialect
                return dialect
            shown = " ".join(reply.split())[:80]
            self.probe_log.append({"dialect": dialect,
                                   "outcome": f"ignored: the reply did not follow the probe "
                                              f"schema: {shown!r}"})
        raise BackendError(f"{self.url}: structured output probe: the server rejected every "
                           f"request shape ({', '.join(AUTO_ORDER)}); last: "
                           f"{self.probe_log[-1]['outcome']}")

    def _request(self, dialect: str, body: bytes) -> str:
        """One request in ``dialect``, retried as the class says; its reply text."""
        url = self.native_url if dialect == "ollama" else self.url
        problems: list[_Failure] = []
        for attempt in range(self.max_retries + 1):
            if attempt:
                time.sleep(self.backoff * 2 ** (attempt - 1) * (1 + random.random() / 4))
            try:
                return self._attempt(url, body, dialect)
            except _Failure as failure:
                problems.append(failure)
                if not failure.retry:
                    break
        last = problems[-1]
        problem, body = last.problem, last.body
        if self.api_key:
            problem, body = (problem.replace(self.api_key, "[API key]"),
                             body.replace(self.api_key, "[API key]"))
        if len(problems) == 1:
            raise BackendError(f"{url}: {problem}", last.status, body)
        raise BackendError(f"{url}: no reply after {len(problems)} attempt(s); last: "
                           f"{problem}", last.status, body)

    def _attempt(self, url: str, body: bytes, dialect: str) -> str:
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
                    client.stream("POST", url, content=body, headers=headers,
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
                           retry=not request_rejected(response.status_code, text),
                           status=response.status_code, body=text)
        return self._content(bytes(payload), url, dialect)

    def _redirect_problem(self, response: httpx.Response) -> str:
        location = response.headers.get("Location")
        try:
            target = response.request.url.join(location) if location else None
        except httpx.InvalidURL:
            target = None
        where = f"to {target.scheme}://{target.netloc.decode()}" if target else "elsewhere"
        return (f"HTTP {response.status_code} redirect {where} not followed (requests and the "
                f"API key go only to the base URL's origin); use the final address as base URL")

    def _content(self, payload: bytes, url: str, dialect: str) -> str:
        try:
            data = load_json(payload, url)
            content = data["message"]["content"] if dialect == "ollama" \
                else data["choices"][0]["message"]["content"]
        except (ValueError, KeyError, IndexError, TypeError):
            what = "an Ollama chat reply" if dialect == "ollama" else "a chat completion"
            raise _Failure(f"the response is not {what}: {payload[:200]!r}", retry=False,
                           status=200, body=payload[:MAX_DETAIL_CHARS].decode(errors="replace")
                           ) from None
        if not isinstance(content, str):
            raise _Failure("the reply has no text content", retry=False)
        if len(content) > self.max_reply_chars:
            content = (content[:self.max_reply_chars] + f"\n[... cut: the reply has "
                       f"{len(content)} characters; at most {self.max_reply_chars} are kept]")
        return content


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

    def __init__(self, replies: Sequence[str | None], name: str = "scripted"):
        self.replies = list(replies)
        self.requests: list[list[Message]] = []
        self.name = name

    def complete(self, messages: Sequence[Message], schema: dict[str, Any] | None = None) -> str:
        self.requests.append(list(messages))
        if len(self.requests) > len(self.replies):
            raise BackendError(f"{self.name}: only {len(self.replies)} scripted repl"
                               f"{'y' if len(self.replies) == 1 else 'ies'}; asked for another")
        reply = self.replies[len(self.requests) - 1]
        if not isinstance(reply, str):
            raise BackendError(f"{self.name}: reply {len(self.requests)} was recorded as a "
                               "failure of the language model, not a reply")
        return reply

    @classmethod
    def from_file(cls, path: str | Path) -> ScriptedBackend:
        """Replies from a JSON file: a list of strings, or of behavior documents (objects)."""
        data = _load_file(path, "scripted replies")
        if not isinstance(data, list) or not data:
            raise BackendError(f"{path}: expected a non-empty JSON list of replies")
        return cls([r if isinstance(r, str) else json.dumps(r, indent=2) for r in data],
                   name=f"scripted replies from {path}")


class TranscriptBackend(ScriptedBackend):
    """Replays the raw replies recorded in a ``vlb synthesize`` transcript (a graph-first one's
    ``rounds``, or an intent-first one's ``drafts`` and their rounds)."""

    @classmethod
    def from_file(cls, path: str | Path) -> TranscriptBackend:
        data = _load_file(path, "transcript")
        try:
            rounds = ([r for d in data["drafts"] for r in d["rounds"]]
                      if isinstance(data, dict) and "drafts" in data else data["rounds"])
            replies = [r["reply"] for r in rounds]
            if not all(r is None or isinstance(r, str) for r in replies):
                raise TypeError
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
