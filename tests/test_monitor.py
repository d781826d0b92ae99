"""vlb monitor: a live page of a running campaign, read-only from its store, in a real browser."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from tests.test_reports import CHROMIUM, CHROMIUM_ARGS
from vlb_gym.reports.monitor import Monitor, snapshot
from vlb_gym.verify.store import open_readonly

VLB = [sys.executable, "-m", "vlb_gym.cli"]


def ctrl_c_as_in_a_terminal() -> None:
    """SIGINT as a terminal's Ctrl-C delivers it, in a child about to be interrupted: a suite
    run in the background has it ignored, and the ignoring is inherited."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def vlb(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([*VLB, *args], cwd=cwd, capture_output=True, text=True, timeout=300)


def status(url: str) -> dict:
    with urllib.request.urlopen(url + "status.json", timeout=30) as answer:
        return json.loads(answer.read())


@pytest.fixture
def serving():
    servers = []

    def serve(path: Path, interval: float = 0.5) -> Monitor:
        server = Monitor(path, 0, interval)
        threading.Thread(target=server.serve_forever, daemon=True).start()
        servers.append(server)
        return server
    yield serve
    for server in servers:
        server.shutdown()
        server.server_close()


def wait_for(condition, seconds: float = 120.0, every: float = 0.2):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(every)
    raise AssertionError("condition not reached in time")


def test_the_page_follows_a_running_campaign_to_its_report(tmp_path, serving):
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    if not Path(CHROMIUM).exists():
        pytest.skip(f"chromium is not installed at {CHROMIUM}")
    store = tmp_path / "run.db"
    command = ["verify", "VLB-GridExplore-v0", "--behavior", "explore_until_goal",
               "--episodes", "4000", "--epsilon", "0.01", "--store", str(store)]
    server = serving(store, interval=0.3)
    campaign = subprocess.Popen([*VLB, *command], cwd=tmp_path, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
    try:
        with sync_api.sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            try:
                page = browser.new_page()
                requests: list[str] = []
                page.on("request", lambda request: requests.append(request.url))
                page.goto(server.url, wait_until="load")

                def shown() -> int:
                    text = page.inner_text("#count")
                    return int(text.split(" of ")[0]) if " of " in text else 0
                first = wait_for(lambda: shown() > 0 and shown() < 4000 and shown())
                assert "running" in page.inner_text("#state")
                later = wait_for(lambda: shown() > first and shown())
                assert later > first  # the counts change while the campaign runs
                assert campaign.wait(timeout=300) == 0, campaign.stderr.read()
                wait_for(lambda: shown() == 4000 and "finished" in page.inner_text("#state"))
                summary = page.inner_text("#summary")
                nodes = page.eval_on_selector_all(
                    "#nodes tbody tr", "rows => rows.map(r => [...r.cells].map(c => c.textContent))")
            finally:
                browser.close()
    finally:
        if campaign.poll() is None:
            campaign.kill()
            campaign.wait()
    report = json.loads(vlb("report", str(store), "--json", cwd=tmp_path).stdout)
    assert f"successes {report['successes']}/4000" in summary
    assert "P[success] >=" in summary and "INCOMPLETE" not in summary
    assert vlb("report", str(store), cwd=tmp_path).stdout.strip() == summary.strip()
    assert {row[0] for row in nodes} == {"sense", "go"}
    assert all(int(row[1]) > 0 and row[2] == "0" and row[4] == "-" for row in nodes)
    assert all(row[5].endswith(" ms") and float(row[5][:-3]) > 0 for row in nodes)
    # the page's node table is the report's
    assert [(n["node"], n["runs"]) for n in report["nodes"]] == [(r[0], int(r[1])) for r in nodes]
    assert all(url.startswith(server.url) for url in requests), requests  # nothing from outside


def test_a_failing_campaign_shows_its_causes_with_replay_commands(tmp_path, serving):
    behavior = tmp_path / "wall.json"
    behavior.write_text(json.dumps({
        "name": "wall", "env": "VLB-GridExplore-v0",
        "nodes": [{"id": "s", "primitive": "sense"}, {"id": "go", "primitive": "navigate"}],
        "start": {"node": "s", "param": "current_cell()"},
        "edges": [{"from": "s", "to": "go", "param": "(0, 0)"}],
        "terminals": ["go"]}))
    store = tmp_path / "wall.db"
    done = vlb("verify", "VLB-GridExplore-v0", "--behavior", str(behavior), "--episodes", "30",
               "--epsilon", "0.1", "--store", str(store), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    state = status(serving(store).url)
    report = json.loads(vlb("report", str(store), "--json", cwd=tmp_path).stdout)
    assert state["done"] == state["planned"] == 30 and state["complete"]
    assert [(f["cause"], f["count"]) for f in state["failures"]] == [
        (g["cause"], g["count"]) for g in report["failures_by_cause"]]
    assert all(f["replay"].startswith(f"vlb replay {store}") for f in state["failures"])
    reader = open_readonly(store)
    try:
        failed = sum(e.failed_certificates for e in reader.results())
    finally:
        reader.close()
    assert sum(n["failed"] for n in state["nodes"]) == failed > 0
    assert state["nodes"] == report["nodes"]  # steps, failures by kind, mean time: the report's
    assert state["nodes"][1]["failures"] == {"navigate: inadmissible parameter": failed}


def test_what_is_not_a_store_is_said_and_only_two_paths_are_served(tmp_path, serving):
    missing = tmp_path / "later.db"
    assert "no such campaign store" in snapshot(missing)["error"]
    server = serving(missing)
    assert "no such campaign store" in status(server.url)["error"]
    not_a_store = tmp_path / "notes.db"
    not_a_store.write_text("hello")
    assert "error" in snapshot(not_a_store)
    for path in ("../etc/passwd", "status.json/..", "x"):
        with pytest.raises(urllib.error.HTTPError) as error:
            urllib.request.urlopen(server.url + path, timeout=30)
        assert error.value.code == 404
    assert not (tmp_path / "later.db").exists()  # the monitor never creates the store


def test_the_command_says_where_it_serves_and_refuses_a_bad_port(tmp_path):
    done = vlb("monitor", str(tmp_path / "s.db"), "--port", "70000", cwd=tmp_path)
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert "at most 65535" in done.stderr
    server = subprocess.Popen([*VLB, "monitor", str(tmp_path / "s.db"), "--port", "0"],
                              cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"},
                              preexec_fn=ctrl_c_as_in_a_terminal)
    try:
        line = server.stdout.readline()
        assert line.startswith("vlb monitor: http://127.0.0.1:") and "does not exist yet" in line
        url = line.split()[2]
        assert "no such campaign store" in status(url)["error"]
    finally:
        server.send_signal(2)
        assert server.wait(timeout=30) == 0
    assert server.stderr.read().strip() == "vlb monitor: stopped"


def test_a_comparison_store_is_shown_in_pairs(tmp_path, serving):
    store = tmp_path / "pairs.db"
    done = vlb("compare", "VLB-GridExplore-v0", "explore_until_goal", "find_goal_and_oscillate",
               "--pairs", "20", "--store", str(store), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    state = status(serving(store).url)
    assert (state["kind"], state["done"], state["planned"], state["complete"]) == (
        "pairs", 20, 20, True)
    assert state["summary"] == vlb("report", str(store), cwd=tmp_path).stdout.strip()


def test_a_request_for_another_host_name_reads_nothing(tmp_path, serving):
    server = serving(tmp_path / "s.db")
    port = server.server_address[1]
    for host, code in ((f"127.0.0.1:{port}", 200), (f"localhost:{port}", 200),
                       (f"evil.example:{port}", 421), ("127.0.0.1", 421)):
        request = urllib.request.Request(server.url + "status.json", headers={"Host": host})
        try:
            with urllib.request.urlopen(request, timeout=30) as answer:
                got = answer.status
        except urllib.error.HTTPError as error:
            got = error.code
        assert got == code, host


@pytest.mark.parametrize("interval", [0.01, 1e7])
def test_an_interval_out_of_bounds_is_refused(tmp_path, interval):
    with pytest.raises(ValueError, match="refreshes every 0.1 to 86400 seconds"):
        Monitor(tmp_path / "s.db", 0, interval)
    done = vlb("monitor", str(tmp_path / "s.db"), "--interval", str(interval), cwd=tmp_path)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
