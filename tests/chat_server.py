"""A real chat-completions HTTP server on 127.0.0.1 for backend tests; it replays a script."""

from __future__ import annotations

import json
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

CHUNK = b"x" * 65536


class ChatServer:
    """Serves ``POST /v1/chat/completions``; each request takes the next scripted action:

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

    Every request (any method, any path) is recorded: its JSON body (or None) in ``requests``, its
    headers in ``headers``. ``sent`` holds how many body bytes each streamed action got out before
    it ended. Leaving the ``with`` block waits for the handlers: streaming ones stop as soon as
    the client hangs up, so the records are complete by then.
    """

    def __init__(self, script):
        self.script = list(script)
        self.requests: list[dict | None] = []
        self.headers: list[dict] = []
        self.sent: list[int] = []
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args):
                """Keep test output clean: no access log."""

            def do_POST(self):
                length = int(self.headers.get("Content-Length", 0))
                raw = self.rfile.read(length)
                server.requests.append(json.loads(raw) if raw else None)
                server.headers.append(dict(self.headers))
                if self.path != "/v1/chat/completions":
                    return self._send(404, b'{"error": "not found"}')
                action = server.script.pop(0) if server.script else ("status", 500)
                try:
                    self._act(*action)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (timeout and size tests)

            do_GET = do_PUT = do_POST

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
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc):
        self.httpd.shutdown()
        self.httpd.server_close()
