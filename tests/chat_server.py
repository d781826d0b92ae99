"""A real chat-completions HTTP server on 127.0.0.1 for backend tests; it replays a script."""

from __future__ import annotations

import json
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer


class ChatServer:
    """Serves ``POST /v1/chat/completions``; each request takes the next scripted action:

    ``("reply", text)`` a completion with that content; ``("status", code)`` an HTTP error;
    ``("sleep", seconds, text)`` a completion sent after a delay; ``("raw", bytes)`` a body as is.
    """

    def __init__(self, script):
        self.script = list(script)
        self.requests: list[dict] = []
        self.headers: list[dict] = []
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args):
                """Keep test output clean: no access log."""

            def do_POST(self):
                length = int(self.headers.get("Content-Length", 0))
                body = json.loads(self.rfile.read(length))
                server.requests.append(body)
                server.headers.append(dict(self.headers))
                if self.path != "/v1/chat/completions":
                    return self._send(404, b'{"error": "not found"}')
                action = server.script.pop(0) if server.script else ("status", 500)
                if action[0] == "status":
                    return self._send(action[1], b'{"error": "scripted failure"}')
                if action[0] == "raw":
                    return self._send(200, action[1])
                if action[0] == "sleep":
                    time.sleep(action[1])
                    action = ("reply", action[2])
                completion = {"id": "x", "object": "chat.completion", "model": body["model"],
                              "choices": [{"index": 0, "finish_reason": "stop", "message": {
                                  "role": "assistant", "content": action[1]}}]}
                self._send(200, json.dumps(completion).encode())

            def _send(self, code, payload):
                try:
                    self.send_response(code)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(len(payload)))
                    self.end_headers()
                    self.wfile.write(payload)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (timeout tests)

        self.httpd = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.httpd.daemon_threads = True
        self.url = f"http://127.0.0.1:{self.httpd.server_address[1]}/v1"
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc):
        self.httpd.shutdown()
        self.httpd.server_close()
