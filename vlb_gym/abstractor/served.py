"""Served language models: the chat-completions protocol over HTTP (httpx).

:class:`OpenAICompatibleBackend` speaks to hosted APIs and to local servers (vLLM, Ollama,
llama.cpp), with structured output in each server's dialect (:data:`DIALECTS`, or ``"auto"``:
probed once). It treats the server as untrusted: no redirect is followed (the API key goes to
the configured origin only), each attempt has a total deadline, replies are size-capped, and
requests the server rejects are not sent again.
"""

from __future__ import annotations

import json
import os
import random
import re
import socket
import threading
import time
from collections.abc import Sequence
from typing import Any

import httpx

from vlb_gym.core.files import load_json

from .backends import ModelError, Message, unrepeated
from .dialects import (ALIASES, AUTO_ORDER, DIALECTS, MAX_DETAIL_CHARS, MAX_REPLY_BYTES,
                       MAX_REPLY_CHARS, MISSING_ENDPOINT, OLLAMA_NUM_CTX, PROBE_MAX_TOKENS,
                       PROBE_MESSAGES, PROBE_SCHEMA, StructuredOutput, probe_reply_ok,
                       request_rejected, server_message, shape_rejected)

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
        self.usage: list[dict[str, Any]] = []  # a server's timings are its own
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
        :class:`ModelError` naming the dialect being probed, not a reason to fall back.
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
            except ModelError as exc:
                if exc.status in MISSING_ENDPOINT and dialect != "ollama":
                    missing = True
                    self.probe_log.append({"dialect": dialect, "outcome": f"no endpoint: {exc}"})
                    continue
                if exc.status is not None and shape_rejected(exc.status, exc.body, dialect):
                    self.probe_log.append({"dialect": dialect, "outcome": f"rejected: {exc}"})
                    continue
                raise ModelError(f"structured output probe ({dialect}): {exc}", exc.status,
                                   exc.body) from None
            if not reply.strip():
                raise ModelError(f"structured output probe ({dialect}): the model replied "
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
        raise ModelError(f"{self.url}: structured output probe: the server rejected every "
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
                return self._redacted(self._attempt(url, body, dialect))
            except _Failure as failure:
                problems.append(failure)
                if not failure.retry:
                    break
        last = problems[-1]
        problem, body = self._redacted(last.problem), self._redacted(last.body)
        if len(problems) == 1:
            raise ModelError(f"{url}: {problem}", last.status, body)
        raise ModelError(f"{url}: no reply after {len(problems)} attempt(s); last: "
                           f"{problem}", last.status, body)

    def _redacted(self, text: str) -> str:
        """``text`` without the API key in any letter case (a server may echo the request's
        headers, upper-cased or not): nothing the backend returns, raises or records holds
        it."""
        if not self.api_key:
            return text
        return re.sub(re.escape(self.api_key), "[API key]", text, flags=re.IGNORECASE)

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
