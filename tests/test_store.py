"""The campaign store: durable episodes, resume after SIGKILL, refusal of foreign files and of
other campaigns, and reports rebuilt from the store alone."""

from __future__ import annotations

import json
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

from vlb_gym.cli import main
from vlb_gym.verify import (CampaignConfig, CampaignStore, StoreError, report_from_store,
                            run_campaign)
from vlb_gym.verify.store import open_readonly, parting

from .conftest import EXAMPLES

GRID = "VLB-GridExplore-v0"
# how a run went, not what it found (a store records what it found)
TIMING = ("wall_seconds", "episodes_per_second", "workers", "backend", "machine")


def comparable(report: dict) -> dict:
    return {k: v for k, v in report.items() if k not in TIMING}


def stored_indices(path) -> list[int]:
    with sqlite3.connect(f"file:{path}?mode=ro", uri=True) as db:
        return [row[0] for row in db.execute("SELECT idx FROM episodes")]


def stored_so_far(path) -> int:
    """Episodes stored by a campaign still starting or running (0 before its tables exist)."""
    try:
        return len(stored_indices(path))
    except sqlite3.OperationalError:
        return 0


@pytest.mark.timeout(180)
def test_a_campaign_killed_with_sigkill_resumes_to_the_uninterrupted_report(tmp_path):
    store = tmp_path / "campaign.db"
    command = [sys.executable, "-m", "vlb_gym.cli", "verify", GRID, "--behavior",
               "examples/fixed_cell.json", "--episodes", "3000", "--epsilon", "0.05", "--seed", "4",
               "--store", str(store), "--report", str(tmp_path / "resumed.json"), "--quiet"]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    proc = subprocess.Popen(command, cwd=root, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while not (store.exists() and stored_so_far(store) >= 200):
        assert proc.poll() is None and time.monotonic() < deadline, proc.communicate()
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    killed_at = len(stored_indices(store))
    assert 200 <= killed_at < 3000
    done = subprocess.run(command, cwd=root, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert f"resuming {store}: {killed_at} of 3000" in done.stderr
    indices = stored_indices(store)
    assert sorted(indices) == list(range(3000))  # each episode exactly once
    resumed = json.loads((tmp_path / "resumed.json").read_text())
    fresh = run_campaign(CampaignConfig(GRID, str(EXAMPLES / "fixed_cell.json"), 3000, seed=4))
    assert comparable(resumed) == comparable(fresh)
    assert resumed["behavior"] == str(EXAMPLES / "fixed_cell.json")  # absolute: any cwd resumes
    rebuilt = report_from_store(CampaignStore(store, readonly=True))
    assert rebuilt["planned_episodes"] == 3000
    assert {k: rebuilt[k] for k in ("successes", "failures", "confidence", "lower_bound",
                                    "failures_by_cause")} == \
           {k: fresh[k] for k in ("successes", "failures", "confidence", "lower_bound",
                                  "failures_by_cause")}


def test_a_store_holding_another_campaign_is_refused_naming_what_differs(tmp_path, capsys):
    store = tmp_path / "s.db"
    base = ["verify", GRID, "--behavior", "find_goal_and_oscillate", "--epsilon", "0.05",
            "--store", str(store), "--quiet"]
    assert main([*base, "--episodes", "20"]) == 0
    capsys.readouterr()
    assert main([*base, "--episodes", "20", "--seed", "1"]) == 2
    assert "holds another campaign (seed: stored 0, now 1)" in capsys.readouterr().err
    assert main([*base, "--episodes", "20", "--env-kwarg", "action_noise=0.5"]) == 2
    err = capsys.readouterr().err
    assert "env_kwargs" in err and "sampling_distribution" in err
    stored, now = re.search(r"sampling_distribution: stored (.*), now (.*)\)$",
                            err.strip()).groups()  # the last key that differs
    assert stored != now and "sigma=0.5" in now and "sigma" not in stored  # where they part
    assert sorted(stored_indices(store)) == list(range(20))  # nothing was added


def test_parting_shows_two_long_values_where_they_differ():
    shared = "x" * 300
    stored, now = parting(shared + "deterministic", shared + "noisy")
    assert stored != now and stored.startswith("…") and "deterministic" in stored
    assert parting(1, 2) == ("1", "2") and parting("ab", "abc") == ("'ab'", "'abc'")


@pytest.mark.parametrize("content", [b"", b"not a database at all" * 100, b"SQLite format 3\0"])
def test_a_foreign_or_corrupt_file_is_refused_and_left_untouched(tmp_path, capsys, content):
    path = tmp_path / "foreign.db"
    path.write_bytes(content)
    if content:
        assert main(["verify", GRID, "--behavior", "find_goal_and_oscillate", "--episodes", "3",
                     "--epsilon", "0.05", "--store", str(path)]) == 2
        assert "not a vlb-gym campaign store" in capsys.readouterr().err
        assert path.read_bytes() == content
    with sqlite3.connect(tmp_path / "other.db") as db:  # a real SQLite file of someone else's
        db.execute("CREATE TABLE notes (x)")
    with pytest.raises(StoreError, match="not a vlb-gym campaign store"):
        CampaignStore(tmp_path / "other.db")


def test_vlb_report_rebuilds_the_report_from_the_store(tmp_path, capsys):
    store = tmp_path / "s.db"
    assert main(["verify", GRID, "--behavior", str(EXAMPLES / "fixed_cell.json"), "--episodes",
                 "50", "--epsilon", "0.05", "--store", str(store), "--report",
                 str(tmp_path / "r.json")]) == 0
    capsys.readouterr()
    assert main(["report", str(store), "--json"]) == 0
    rebuilt = json.loads(capsys.readouterr().out)
    original = json.loads((tmp_path / "r.json").read_text())
    nodes = rebuilt.pop("nodes")  # the store has every step: the report adds each node's
    assert comparable({**rebuilt, "planned_episodes": None}) == \
        comparable({**original, "planned_episodes": None})
    reader = open_readonly(store)
    try:
        steps = [step for episode in reader.results() for step in episode.steps]
    finally:
        reader.close()
    assert sum(node["runs"] for node in nodes) == len(steps) > 0
    assert sum(node["failed"] for node in nodes) == sum(not s["certificate"] for s in steps)
    assert all(node["mean_seconds"] > 0 for node in nodes if node["runs"])
    assert main(["report", str(store)]) == 0
    assert f"successes {original['successes']}/50, failures {original['failures']}" in \
        capsys.readouterr().out
    assert main(["report", str(tmp_path / "missing.db")]) == 2
    assert "no such campaign store" in capsys.readouterr().err


def test_a_store_in_use_by_another_campaign_is_refused(tmp_path):
    first = CampaignStore(tmp_path / "s.db")
    with pytest.raises(StoreError, match="in use by another process"):
        CampaignStore(tmp_path / "s.db")
    first.close()
    CampaignStore(tmp_path / "s.db").close()  # free again once closed
