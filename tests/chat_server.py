"""A real chat-completions HTTP server on 127.0.0.1 for backend tests; it replays a script, and
in a dialect mode it answers structured-output requests the way a kind of real server does."""

from __future__ import annotations

import json
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

try:  # a constrained decoder's guarantee, checked where the test environment can
    import jsonschema
except ImportError:  # pragma: no cover
    jsonschema = None

CHUNK = b"x" * 65536
CHAT_PATH = "/v1/chat/completions"
OLLAMA_PATH = "/api/chat"
PROBE_MARK = "connection test"

# what llama-cpp-python's server answers to a response_format type it does not support (pydantic)
LLAMA_CPP_VALIDATION_500 = json.dumps({"error": {"message": (
    "[{'type': 'literal_error', 'loc': ('body', 'response_format', 'type'), 'msg': \"Input "
    "should be 'text' or 'json_object'\", 'input': 'json_schema', 'ctx': {'expected': \"'text' "
    "or 'json_object'\"}}]"), "type": "internal_server_error"}}).encode()
# what an older vLLM (before response_format json_schema) answers to it
VLLM_VALIDATION_400 = json.dumps({"object": "error", "message": (
    "[{'type': 'literal_error', 'loc': ('body', 'response_format', 'type'), 'msg': \"Input "
    "should be 'text' or 'json_object'\", 'input': 'json_schema'}]"), "type": "BadRequestError",
    "code": 400}).encode()


def _openai_error(message: str) -> bytes:
    return json.dumps({"error": {"message": message, "type": "invalid_request_error",
                                 "param": None, "code": None}}).encode()


NOT_FOUND = (404, b'{"error": "not found"}')


def shape_of(path: str, body: dict | None) -> str:
    """The structured-output dialect a request is written in (``behavior`` is not one: see
    :class:`ChatServer`'s ``shapes``)."""
    body = body or {}
    if path == OLLAMA_PATH:
        return "ollama"
    if "guided_json" in body:
        return "vllm"
    fmt = body.get("response_format") or {}
    if fmt.get("type") == "json_schema":
        return "openai"
    if fmt.get("type") == "json_object":
        return "llamacpp" if "schema" in fmt else "json_object"
    return "none"


def _openai(path, body):
    """OpenAI: json_schema and json_object honoured; unknown parameters refused with 400."""
    if path != CHAT_PATH:
        return ("reject", *NOT_FOUND)
    if "guided_json" in body:
        return ("reject", 400, _openai_error("Unrecognized request argument supplied: "
                                             "guided_json"))
    fmt = body.get("response_format")
    if fmt is None:
        return ("free",)
    if fmt.get("type") == "json_schema":
        return ("schema", fmt["json_schema"]["schema"])
    if fmt == {"type": "json_object"}:
        return ("json",)
    return ("reject", 400, _openai_error("Invalid parameter: 'response_format' must be text, "
                                         "json_object or json_schema, with no other keys"))


def _llamacpp(path, body):
    """llama-cpp-python's server: json_object (+ schema) honoured, json_schema refused with its
    HTTP 500 validation error, fields it does not know (guided_json) ignored."""
    if path != CHAT_PATH:
        return ("reject", *NOT_FOUND)
    fmt = body.get("response_format")
    if fmt is None:
        return ("free",)
    if fmt.get("type") not in ("text", "json_object"):
        return ("reject", 500, LLAMA_CPP_VALIDATION_500)
    if fmt.get("type") == "json_object":
        return ("schema", fmt["schema"]) if "schema" in fmt else ("json",)
    return ("free",)


def _vllm(path, body):
    """An older vLLM: guided_json honoured; response_format json_schema refused with HTTP 400
    (its pydantic literal error); json_object honoured as JSON mode, an extra ``schema`` key in
    it ignored (vLLM ignores fields it does not know, with a warning in its log)."""
    if path != CHAT_PATH:
        return ("reject", *NOT_FOUND)
    if "guided_json" in body:
        return ("schema", body["guided_json"])
    fmt = body.get("response_format")
    if fmt is None or fmt.get("type") == "text":
        return ("free",)
    if fmt.get("type") == "json_object":
        return ("json",)
    return ("reject", 400, VLLM_VALIDATION_400)


def _ollama(path, body):
    """Ollama before 0.5: the native /api/chat honours ``format`` (a schema, or "json"); its
    OpenAI-compatible /v1 honours json_object (as format "json", the schema key ignored) and
    ignores everything else (json_schema, guided_json)."""
    if path == OLLAMA_PATH:
        fmt = body.get("format")
        if isinstance(fmt, dict):
            return ("schema", fmt)
        return ("json",) if fmt == "json" else ("free",)
    if path != CHAT_PATH:
        return ("reject", *NOT_FOUND)
    fmt = body.get("response_format") or {}
    return ("json",) if fmt.get("type") == "json_object" else ("free",)


def _json_mode(path, body):
    """A strict server with JSON mode only: any other structured-output field is a 400."""
    if path != CHAT_PATH:
        return ("reject", *NOT_FOUND)
    if "guided_json" in body:
        return ("reject", 400, _openai_error("unknown field: guided_json"))
    fmt = body.get("response_format")
    if fmt is None:
        return ("free",)
    if fmt == {"type": "json_object"}:
        return ("json",)
    return ("reject", 400, _openai_error("response_format: only {'type': 'json_object'} is "
                                         "supported"))


def _text(path, body):
    """A strict server with no structured output at all."""
    if path != CHAT_PATH:
        return ("reject", *NOT_FOUND)
    if "guided_json" in body or "response_format" in body:
        return ("reject", 422, json.dumps({"detail": [{"loc": ["body", "response_format"],
                                                       "msg": "extra fields not permitted"}]}
                                          ).encode())
    return ("free",)


DIALECT_SERVERS = {"openai": _openai, "llamacpp": _llamacpp, "vllm": _vllm, "ollama": _ollama,
                   "json_mode": _json_mode, "text": _text}


def instance(schema: dict):
    """The smallest document of a (probe-sized) schema: what a constrained decoder must write."""
    if "const" in schema:
        return schema["const"]
    if "enum" in schema:
        return schema["enum"][0]
    kind = schema.get("type")
    if kind == "object":
        return {key: instance(schema["properties"][key]) for key in schema.get("required", [])}
    return {"boolean": True, "string": "x", "integer": 0, "number": 0, "null": None,
            "array": []}[kind]


class ChatServer:
    """Serves ``POST /v1/chat/completions`` (and Ollama's ``POST /api/chat``, whose replies are in
    Ollama's shape); each request takes the next scripted action:

    * ``("reply", text)`` a completion with that content;
    * ``("status", code)`` or ``("status", code, body)`` an HTTP error (``body``: bytes);
    * ``("sleep", seconds, text)`` a completion sent after a delay;
    * ``("raw", body)`` or ``("raw", body, headers)`` a 200 with that body (bytes) as is;
    * ``("redirect", location)`` a 302 to ``location``;
    * ``("drip", interval, size)`` a 200 announcing ``size`` bytes, then sending one per
      ``interval`` seconds;
    * ``("drip_headers", interval, count)`` a status line, then one header byte per ``interval``
      seconds, ``count`` of them, never finishing the headers;
    * ``("endless",)`` a 200 with a chunked body that never ends;
    * ``("huge", size)`` a 200 with a ``size``-byte body, sent as fast as the client reads.

    With ``dialect`` (a key of :data:`DIALECT_SERVERS`) the server also serves Ollama's
    ``POST /api/chat`` and judges each request's structured-output fields as that kind of server
    does (each mode's docstring says how): a request it refuses gets its error and takes no
    action; a probe (its last message says "connection test") is answered without the script --
    with the smallest document of the schema where the server enforces one, ``{"ok": true}`` (an
    obliging model) where it does not; any other request takes the next scripted action, whose
    reply, where the server enforces a schema, must match it (as a constrained decoder would
    make it). ``shapes`` lists the dialect each request was written in (:func:`shape_of`), with
    ``behavior`` for requests that are not probes.

    Every request (any method, any path) is recorded: its JSON body (or None) in ``requests``, its
    path in ``paths``, its headers in ``headers``. ``sent`` holds how many body bytes each streamed action got out before
    it ended. Leaving the ``with`` block waits for the handlers: streaming ones stop as soon as
    the client hangs up, so the records are complete by then.
    """

    def __init__(self, script=(), dialect: str | None = None):
        self.script = list(script)
        self.dialect = DIALECT_SERVERS[dialect] if dialect else None
        self.requests: list[dict | None] = []
        self.paths: list[str] = []
        self.shapes: list[str] = []
        self.headers: list[dict] = []
        self.sent: list[int] = []
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args):
                """Keep test output clean: no access log."""

            def do_POST(self):
                length = int(self.headers.get("Content-Length", 0))
                raw = self.rfile.read(length)
                body = json.loads(raw) if raw else None
                server.requests.append(body)
                server.paths.append(self.path)
                server.headers.append(dict(self.headers))
                if server.dialect is not None:
                    return self._dialect(body or {})
                if self.path not in (CHAT_PATH, OLLAMA_PATH):
                    return self._send(*NOT_FOUND)
                action = server.script.pop(0) if server.script else ("status", 500)
                try:
                    self._act(*action)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (timeout and size tests)

            do_GET = do_PUT = do_POST

            def _dialect(self, body):
                verdict, *args = server.dialect(self.path, body)
                messages = body.get("messages") or [{}]
                probe = PROBE_MARK in str(messages[-1].get("content", ""))
                server.shapes.append(shape_of(self.path, body) if probe else "behavior")
                if verdict == "reject":
                    return self._send(*args)
                if probe:
                    content = json.dumps(instance(args[0]) if verdict == "schema"
                                         else {"ok": True})
                else:
                    kind, *rest = server.script.pop(0) if server.script else ("status", 500)
                    if kind != "reply":
                        return self._act(kind, *rest)
                    content = rest[0]
                    if verdict == "schema" and jsonschema is not None:
                        try:
                            jsonschema.validate(json.loads(content), args[0])
                        except (ValueError, jsonschema.ValidationError) as exc:
                            message = f"test server: the scripted reply breaks the schema: {exc}"
                            return self._send(500, json.dumps({"error": message[:500]}).encode())
                return self._act("reply", content)

            def _act(self, kind, *args):
                if kind == "status":
                    return self._send(args[0], args[1] if len(args) > 1
                                      else b'{"error": "scripted failure"}')
                if kind == "raw":
                    return self._send(200, *args)
                if kind == "redirect":
                    return self._send(302, b"", {"Location": args[0]})
                if kind == "drip":
                    return self._stream({"Content-Length": str(args[1])},
                                        (b"x" for _ in range(args[1])), args[0])
                if kind == "drip_headers":
                    self.wfile.write(b"HTTP/1.0 200 OK\r\nX-Slow: ")
                    return self._stream(None, (b"x" for _ in range(args[1])), args[0])
                if kind == "endless":
                    self.protocol_version = "HTTP/1.1"
                    self.close_connection = True
                    chunk = b"%x\r\n%s\r\n" % (len(CHUNK), CHUNK)
                    return self._stream({"Transfer-Encoding": "chunked"}, iter(lambda: chunk, b""))
                if kind == "huge":
                    size = args[0]
                    return self._stream({"Content-Length": str(size)},
                                        (CHUNK[:min(len(CHUNK), size - at)]
                                         for at in range(0, size, len(CHUNK))))
                if kind == "sleep":
                    time.sleep(args[0])
                    kind, args = "reply", args[1:]
                assert kind == "reply", kind
                model = (server.requests[-1] or {}).get("model")
                if self.path == OLLAMA_PATH:
                    reply = {"model": model, "message": {"role": "assistant", "content": args[0]},
                             "done": True}
                    return self._send(200, json.dumps(reply).encode())
                completion = {"id": "x", "object": "chat.completion", "model": model,
                              "choices": [{"index": 0, "finish_reason": "stop", "message": {
                                  "role": "assistant", "content": args[0]}}]}
                self._send(200, json.dumps(completion).encode())

            def _send(self, code, payload, headers=None):
                self.send_response(code)
                self.send_header("Content-Type", "application/json")
                self.send_header("Content-Length", str(len(payload)))
                for key, value in (headers or {}).items():
                    self.send_header(key, value)
                self.end_headers()
                self.wfile.write(payload)

            def _stream(self, headers, pieces, interval=0.0):
                """Send ``headers`` (None: none, the status line is out) then ``pieces``."""
                sent = 0
                try:
                    if headers is not None:
                        self.send_response(200)
                        self.send_header("Content-Type", "application/json")
                        for key, value in headers.items():
                            self.send_header(key, value)
                        self.end_headers()
                    for piece in pieces:
                        self.wfile.write(piece)
                        sent += len(piece)
                        time.sleep(interval)
                finally:
                    server.sent.append(sent)

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = False  # so that server_close() waits for the handlers
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}/v1"
        self.origin = f"http://127.0.0.1:{self.httpd.server_address[1]}"
        self.thread = threading.Thread(target=self.httpd.serve_forever, args=(0.05,),
                                       daemon=True)

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc):
        self.httpd.shutdown()
        self.httpd.server_close()
