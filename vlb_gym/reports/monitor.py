"""A live view of a running campaign or comparison: a local page that refreshes from its store.

:func:`snapshot` reads the store read-only (it never writes beside it, and a campaign may be
writing it: SQLite's readers and its one writer do not block each other) and says where the
campaign stands: episodes (or pairs) done of planned, the current guarantee or the sequential
test's state in the words ``vlb verify`` prints, failures by cause with the command that
replays one, and each node's steps and failed certificates. :class:`Monitor` serves it on
127.0.0.1: ``/`` is a page that asks for ``/status.json`` every few seconds; nothing else is
served, and nothing on the page comes from outside this machine.
"""

from __future__ import annotations

import html
import json
import os
import sqlite3
import sys
import threading
import time
from collections import deque
from dataclasses import dataclass, field
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

from vlb_gym.core.errors import UserError
from vlb_gym.core.text import single_line
from vlb_gym.reports import attribution

RATE_WINDOW = 30.0  # seconds of polls the rate is measured over
MIN_INTERVAL, MAX_INTERVAL = 0.1, 86_400.0  # seconds between the page's refreshes
SPARE = 5.0  # after a snapshot that took t seconds, the next one waits SPARE * t


def snapshot(path: str | Path) -> dict[str, Any]:
    """Where the campaign or comparison stored at ``path`` stands (``error``: why it cannot be
    told, e.g. no episode stored yet, or the file is gone or unreadable)."""
    from vlb_gym.verify import comparison
    from vlb_gym.verify.campaign import report_and_records
    from vlb_gym.verify.store import ComparisonStore, open_readonly

    try:
        store = open_readonly(path)
        try:
            if isinstance(store, ComparisonStore):
                report: Any = comparison.report_from_store(store)
                done, planned, unit, nodes = (report["pairs"], report["planned_pairs"], "pairs",
                                              [])
            else:
                report, plan, records = report_and_records(store)
                done, planned, unit = report["episodes"], report["planned_episodes"], "episodes"
                nodes = attribution.node_rows(plan, [r.to_dict() for r in records],
                                              str(report.get("behavior", "")))
        finally:
            store.close()
    except (UserError, OSError, sqlite3.DatabaseError, ValueError) as exc:
        return {"error": single_line(str(exc)) or type(exc).__name__}
    failures = [{"cause": group["cause"], "count": group["count"],
                 "replay": _replay(report, group)}
                for group in report.get("failures_by_cause", [])]
    return {"title": f"{report['env_id']} / {report.get('behavior') or report.get('mode')}",
            "kind": unit, "done": done, "planned": planned, "complete": report["complete"],
            "summary": report.summary(), "failures": failures, "nodes": nodes}


def _replay(report: Any, group: dict[str, Any]) -> str | None:
    replay = getattr(report, "replay_command", None)
    if replay is None or not group.get("episodes"):
        return None
    return replay(group["episodes"][0], group["seeds"][0])


@dataclass
class Status:
    """The latest snapshot of one store, taken again only when the store's files changed (and
    not sooner than :data:`SPARE` times the last one took), and the rate of episodes measured
    over the last :data:`RATE_WINDOW` seconds of polls."""

    path: Path
    _lock: threading.Lock = field(default_factory=threading.Lock)
    _stamp: tuple[Any, ...] | None = None
    _last: dict[str, Any] = field(default_factory=dict)
    _polls: deque[tuple[float, int]] = field(default_factory=deque)
    _next: float = 0.0  # no new snapshot before this time (time.monotonic)

    def _files(self) -> tuple[Any, ...]:
        stamp = []
        for suffix in ("", "-wal"):
            try:
                stat = os.stat(f"{self.path}{suffix}")
                stamp.append((stat.st_mtime_ns, stat.st_size))
            except OSError:
                stamp.append(None)
        return tuple(stamp)

    def current(self) -> dict[str, Any]:
        with self._lock:
            stamp, now = self._files(), time.monotonic()
            if (stamp != self._stamp or "error" in self._last) and now >= self._next:
                self._last, self._stamp = snapshot(self.path), stamp
                # a snapshot reads the whole store: at most a sixth of one core goes to it,
                # however large the store grows, the rest to the campaign
                ended = time.monotonic()
                self._next = ended + SPARE * (ended - now)
            now, done = time.monotonic(), int(self._last.get("done", 0))
            self._polls.append((now, done))
            while self._polls and now - self._polls[0][0] > RATE_WINDOW:
                self._polls.popleft()
            first_time, first_done = self._polls[0]
            rate = (done - first_done) / (now - first_time) if now > first_time else 0.0
            return {**self._last, "per_second": round(rate, 2),
                    "updated": time.strftime("%H:%M:%S")}


PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>vlb monitor</title>
<style>
body{font-family:system-ui,sans-serif;margin:2em;max-width:70em;color:#222}
pre{background:#f6f6f6;padding:1em;white-space:pre-wrap}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:.3em .6em}
td.n{text-align:right}progress{width:30em;height:1.2em}.muted{color:#777}
</style></head><body>
<h1 id="title">vlb monitor</h1>
<p><progress id="bar" value="0" max="1"></progress> <span id="count"></span>
<span id="rate"></span> <span id="state" class="muted"></span></p>
<pre id="summary">waiting for the store...</pre>
<h2>Failures by cause</h2><table id="failures"><thead><tr><th>cause</th><th>count</th>
<th>replay one</th></tr></thead><tbody></tbody></table>
<h2>Nodes</h2><table id="nodes"><thead><tr><th>node</th><th>steps</th><th>failed</th>
<th>failed share</th><th>failures by kind</th><th>mean time of a step</th></tr></thead>
<tbody></tbody></table>
<p class="muted">Refreshes every INTERVAL s from STORE (read-only).</p>
<script>
function fill(id, rows) {
  const body = document.querySelector('#' + id + ' tbody');
  body.replaceChildren(...rows.map(cells => {
    const tr = document.createElement('tr');
    cells.forEach(([text, numeric]) => {
      const td = document.createElement('td');
      td.textContent = text; if (numeric) td.className = 'n'; tr.appendChild(td);
    });
    return tr;
  }));
}
async function refresh() {
  try {
    const s = await (await fetch('status.json', {cache: 'no-store'})).json();
    if (s.error) { document.getElementById('summary').textContent = s.error; return; }
    document.getElementById('title').textContent = s.title;
    const bar = document.getElementById('bar');
    bar.max = s.planned; bar.value = s.done;
    document.getElementById('count').textContent = s.done + ' of ' + s.planned + ' ' + s.kind;
    document.getElementById('rate').textContent = ', ' + s.per_second + ' ' + s.kind + '/s';
    document.getElementById('state').textContent =
      (s.complete ? ' finished' : ' running') + ' (as of ' + s.updated + ')';
    document.getElementById('summary').textContent = s.summary;
    fill('failures', s.failures.map(f => [[f.cause], [String(f.count), 1], [f.replay || '-']]));
    fill('nodes', s.nodes.map(n => [[n.node], [String(n.runs), 1], [String(n.failed), 1],
      [n.runs ? (100 * n.failed / n.runs).toFixed(2) + '%' : '-', 1],
      [Object.entries(n.failures).map(([k, c]) => k + ': ' + c).join('; ') || '-'],
      [n.mean_seconds === null ? '-' : (1000 * n.mean_seconds).toFixed(2) + ' ms', 1]]));
  } catch (e) {
    document.getElementById('state').textContent = ' (monitor unreachable: ' + e + ')';
  }
}
refresh(); setInterval(refresh, INTERVAL * 1000);
</script></body></html>
"""


class Monitor(ThreadingHTTPServer):
    """The live view of the store at ``path`` on ``127.0.0.1:port`` (0: any free port)."""

    daemon_threads = True

    def __init__(self, path: str | Path, port: int = 0, interval: float = 2.0):
        if not MIN_INTERVAL <= interval <= MAX_INTERVAL:
            raise ValueError(f"--interval {interval:g}: the page refreshes every "
                             f"{MIN_INTERVAL:g} to {MAX_INTERVAL:g} seconds")
        self.status = Status(Path(path))
        self.page = (PAGE.replace("INTERVAL", f"{interval:g}")
                     .replace("STORE", html.escape(str(path)))).encode()
        super().__init__(("127.0.0.1", port), _Handler)

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.server_address[1]}/"

    def handle_error(self, request: Any, client_address: Any) -> None:
        """A browser that went away mid-answer is not an error; anything else is one line."""
        error = sys.exc_info()[1]
        if not isinstance(error, ConnectionError):
            print(f"vlb monitor: a request failed: {type(error).__name__}: {error}",
                  file=sys.stderr)


class _Handler(BaseHTTPRequestHandler):
    server: Monitor

    def do_GET(self) -> None:  # noqa: N802 - the http.server interface
        port = self.server.server_address[1]
        if self.headers.get("Host") not in (f"127.0.0.1:{port}", f"localhost:{port}"):
            # a page elsewhere whose name was made to point here (DNS rebinding) reads nothing
            self.send_error(HTTPStatus.MISDIRECTED_REQUEST)
            return
        route = self.path.split("?")[0]
        if route == "/":
            self._send(self.server.page, "text/html; charset=utf-8")
        elif route == "/status.json":
            body = json.dumps(self.server.status.current(), allow_nan=False).encode()
            self._send(body, "application/json")
        else:
            self.send_error(HTTPStatus.NOT_FOUND)

    def _send(self, body: bytes, kind: str) -> None:
        self.send_response(HTTPStatus.OK)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - quiet by design
        """Requests are not logged to the terminal."""
