"""Format versions: files written by earlier vlb-gyms still read (committed fixtures of each
kind and format), today's files carry the current format, and later formats are refused."""

from __future__ import annotations

import json
import shutil
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from vlb_gym.core.formats import CURRENT, FormatError, check_format
from vlb_gym.core.library import BehaviorLibrary, spec_json
from vlb_gym.core.spec import BehaviorSpecError, parse_spec
from vlb_gym.verify import comparison
from vlb_gym.verify.campaign import Campaign, report_from_store, run_campaign
from vlb_gym.verify.records import CampaignConfig
from vlb_gym.verify.export import read_export
from vlb_gym.verify.store import CampaignStore, StoreError, open_readonly

FIXTURES = Path(__file__).parent / "fixtures" / "formats"
V1 = FIXTURES / "v1"
V2 = FIXTURES / "v2"  # stores and exports whose steps record their time
VLB = [sys.executable, "-m", "vlb_gym.cli"]
COMMAND = ["verify", "VLB-GridExplore-v0", "--behavior", "behavior.json", "--env-kwarg",
           "action_noise=1.0", "--episodes", "30", "--epsilon", "0.1", "--seed", "3", "--quiet"]
"""The command that wrote the fixture store (tests/fixtures/formats/make.sh v1)."""


def load_spec(path: Path):
    return parse_spec(path.read_text(), str(path))


def vlb(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([*VLB, *args], cwd=cwd, capture_output=True, text=True, timeout=300)


@pytest.fixture
def v1(tmp_path) -> Path:
    """A copy of the format-1 fixtures (readers must not need to write beside them, but a
    resumed campaign does)."""
    return Path(shutil.copytree(V1, tmp_path / "v1"))


def test_every_kind_has_a_fixture_of_every_format():
    for kind, current in CURRENT.items():
        for version in range(1, current + 1):
            assert (FIXTURES / f"v{version}").is_dir(), (kind, version)
    assert {p.name for p in V1.iterdir()} >= {"behavior.json", "campaign.db", "report.json",
                                              "episodes.jsonl", "comparison.db"}


def test_a_format_1_store_reads_to_the_report_that_was_written_beside_it(v1):
    written = json.loads((v1 / "report.json").read_text())
    assert "format" not in written  # written before versions
    store = open_readonly(v1 / "campaign.db")
    try:
        report, episodes = report_from_store(store), store.results()
    finally:
        store.close()
    for key in ("successes", "episodes", "failures", "lower_bound", "confidence", "content_sha256",
                "failures_by_cause", "sampling_distribution", "seed"):
        assert report[key] == written[key], key
    assert sum(e.success for e in episodes) == written["successes"] > 0
    assert written["failures"] > 0  # the fixture holds failed episodes, with their reasons
    printed = vlb("report", str(v1 / "campaign.db"), "--json", cwd=v1)
    assert printed.returncode == 0 and json.loads(printed.stdout)["format"] == CURRENT["report"]


@pytest.mark.parametrize("rewritten", [False, True])
def test_a_format_1_plan_is_the_plan_today_makes(v1, rewritten):
    """The plan recorded at 6be0ec1 (the behavior's digest and documents) is the one today's
    engine makes of the same file, and of the file written back in the current format: a
    stored campaign or certificate is not refused as another behavior's."""
    if rewritten:
        (v1 / "behavior.json").write_text(spec_json(load_spec(v1 / "behavior.json")))
        assert '"format": 1' in (v1 / "behavior.json").read_text()
    store = open_readonly(v1 / "campaign.db")
    try:
        stored = store.plan()
    finally:
        store.close()
    config = CampaignConfig("VLB-GridExplore-v0", str(v1 / "behavior.json"), 30, 0.1, seed=3,
                            env_kwargs={"action_noise": 1.0})
    with Campaign(config) as campaign:
        today = campaign.plan
    assert today.content_sha256 == stored.content_sha256
    assert list(today.policy_content["behaviors"].values()) == list(
        stored.policy_content["behaviors"].values())
    assert today.sampling_distribution == stored.sampling_distribution


def test_a_format_1_export_reads_as_its_store(v1):
    plan, episodes, end = read_export(v1 / "episodes.jsonl")
    store = open_readonly(v1 / "campaign.db")
    try:
        assert plan == store.plan()
        assert episodes == store.results()
    finally:
        store.close()
    assert end == {"complete": True, "episodes": 30}


@pytest.mark.parametrize("folder", [V1, V2])
def test_steps_of_each_format_read_with_their_times_or_none(folder):
    """Format 1 recorded no step times (None); format 2 records each step's, which sum to at
    most the episode's own time."""
    store = open_readonly(folder / "campaign.db")
    try:
        episodes = store.results()
    finally:
        store.close()
    assert episodes == read_export(folder / "episodes.jsonl")[1]
    for episode in episodes:
        times = [step["seconds"] for step in episode.steps]
        if folder == V1:
            assert times == [None] * len(times)
        else:
            assert all(t > 0 for t in times) and sum(times) <= episode.seconds


def test_a_format_2_store_reads_to_the_report_that_was_written_beside_it():
    written = json.loads((V2 / "report.json").read_text())
    store = open_readonly(V2 / "campaign.db")
    try:
        report = report_from_store(store)
    finally:
        store.close()
    for key in ("successes", "episodes", "failures", "lower_bound", "confidence",
                "content_sha256", "failures_by_cause", "seed"):
        assert report[key] == written[key], key
    printed = vlb("report", str(V2 / "campaign.db"), "--json", cwd=V2)
    nodes = json.loads(printed.stdout)["nodes"]
    assert all(node["mean_seconds"] > 0 for node in nodes if node["runs"])


def test_a_format_1_store_says_the_current_format_from_its_first_new_record(v1):
    """Opened (even refused for another plan, or with nothing left to run) a format-1 store is
    left as it was; a resumed one that gets a new record says the current format."""
    path = v1 / "campaign.db"
    before = path.read_bytes()
    CampaignStore(path).close()
    done = vlb(*[a if a != "0.1" else "0.2" for a in COMMAND], "--store", "campaign.db", cwd=v1)
    assert done.returncode == 2 and "holds another campaign" in done.stderr
    assert path.read_bytes()[:100] == before[:100]  # the header: user_version still 0
    # a format-1 store of a campaign this tree can resume (the fixture's plan names the folder
    # it was written in): today's store written back as format 1 wrote it
    config = CampaignConfig("VLB-GridExplore-v0", "explore_until_goal", 30, 0.1)
    path = v1 / "mine.db"
    store = CampaignStore(path)
    try:
        run_campaign(config, store=store)
    finally:
        store.close()
    with sqlite3.connect(path) as db:
        for idx, text in db.execute("SELECT idx, record FROM episodes").fetchall():
            record = json.loads(text)
            record["steps"] = [step[:-1] for step in record["steps"]]  # no time: format 1
            db.execute("UPDATE episodes SET record = ? WHERE idx = ?", (json.dumps(record), idx))
        db.execute("DELETE FROM episodes WHERE idx >= 25")
        db.execute("PRAGMA user_version=0")
    store = CampaignStore(path)
    try:
        report = run_campaign(config, store=store)
    finally:
        store.close()
    assert report["episodes"] == 30
    with sqlite3.connect(path) as db:
        assert db.execute("PRAGMA user_version").fetchone() == (CURRENT["store"],)
    reader = open_readonly(path)
    try:
        steps = [e.steps for e in reader.results()]
    finally:
        reader.close()
    assert steps[0][0]["seconds"] is None and steps[-1][0]["seconds"] > 0  # both formats read


def test_a_format_1_comparison_store_reads(v1, monkeypatch):
    monkeypatch.chdir(v1)  # the summary shows paths as the command would, from where it runs
    store = open_readonly(v1 / "comparison.db")
    try:
        report = comparison.report_from_store(store)
    finally:
        store.close()
    assert report["pairs"] == report["planned_pairs"] == 12 and report["complete"]
    printed = vlb("report", str(v1 / "comparison.db"), cwd=v1)
    assert printed.returncode == 0 and printed.stdout.strip() == report.summary().strip()


def test_a_format_1_behavior_file_loads_and_is_written_back_in_the_current_format(tmp_path):
    spec = load_spec(V1 / "behavior.json")
    assert spec.format is None
    written = json.loads(spec_json(spec))
    assert written["format"] == CURRENT["behavior"]
    again = tmp_path / "again.json"
    again.write_text(spec_json(spec))
    assert load_spec(again).model_dump(exclude={"format"}) == spec.model_dump(exclude={"format"})
    # the format is not the behavior's content: its digest is the same with or without one
    assert spec_json(load_spec(again), content_only=True) == spec_json(spec, content_only=True)


def test_files_written_today_carry_the_current_format(tmp_path):
    done = vlb("verify", "VLB-GridExplore-v0", "--behavior", "explore_until_goal", "--episodes",
               "3", "--epsilon", "0.5", "--store", "s.db", "--report", "r.json",
               "--episodes-out", "e.jsonl", "--quiet", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    with sqlite3.connect(tmp_path / "s.db") as db:
        assert db.execute("PRAGMA user_version").fetchone() == (CURRENT["store"],)
    assert json.loads((tmp_path / "r.json").read_text())["format"] == CURRENT["report"]
    first = json.loads((tmp_path / "e.jsonl").read_text().splitlines()[0])
    assert first["format"] == CURRENT["export"]
    library = BehaviorLibrary(tmp_path / "library")
    spec = load_spec(V1 / "behavior.json").model_copy(update={"name": "mine"})
    assert json.loads(library.save(spec).read_text())["format"] == CURRENT["behavior"]


@pytest.mark.parametrize("found, words", [(None, None), (1, None), (2, "newer vlb-gym"),
                                          (0, "positive integer"), ("1", "positive integer"),
                                          (True, "positive integer"), (1.0, "positive integer")])
def test_check_format(found, words):
    if words is None:
        assert check_format("behavior", found, "f.json") == 1
    else:
        with pytest.raises(FormatError, match=words):
            check_format("behavior", found, "f.json")


def test_a_behavior_file_of_a_later_format_is_refused_in_one_line(tmp_path):
    data = json.loads((V1 / "behavior.json").read_text())
    path = tmp_path / "later.json"
    path.write_text(json.dumps({**data, "format": CURRENT["behavior"] + 1}))
    with pytest.raises(BehaviorSpecError, match="newer vlb-gym"):
        load_spec(path)
    done = vlb("verify", "VLB-GridExplore-v0", "--behavior", str(path), "--episodes", "3",
               "--epsilon", "0.5", cwd=tmp_path)
    assert done.returncode == 2 and done.stderr.count("\n") == 1
    assert str(path) in done.stderr and "format" in done.stderr and "upgrade" in done.stderr


def test_a_store_of_a_later_format_is_refused_and_left_as_it_was(v1):
    path = v1 / "campaign.db"
    with sqlite3.connect(path) as db:
        db.execute(f"PRAGMA user_version={CURRENT['store'] + 1}")
    before = path.read_bytes()
    with pytest.raises(StoreError, match="newer vlb-gym"):
        open_readonly(path)
    for command in (["report", "campaign.db"], [*COMMAND, "--store", "campaign.db"]):
        done = vlb(*command, cwd=v1)
        assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
        assert f"store format {CURRENT['store'] + 1} was written by a newer vlb-gym" in \
            done.stderr
    assert path.read_bytes() == before


def test_an_export_of_a_later_format_is_refused(tmp_path):
    lines = (V1 / "episodes.jsonl").read_text().splitlines()
    first = json.loads(lines[0])
    path = tmp_path / "later.jsonl"
    path.write_text("\n".join([json.dumps({**first, "format": CURRENT["export"] + 1}),
                               *lines[1:]]) + "\n")
    with pytest.raises(FormatError, match=f"line 1: export format {CURRENT['export'] + 1}"):
        read_export(path)


@pytest.mark.parametrize("version, words", [(-1, "must be a positive integer"),
                                             (2**31 - 1, "format 2147483647 was written by a newer")])
def test_a_store_whose_version_is_no_format_is_refused_in_one_line(v1, version, words):
    path = v1 / "campaign.db"
    with sqlite3.connect(path) as db:
        db.execute(f"PRAGMA user_version={version}")
    done = vlb("report", "campaign.db", cwd=v1)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert words in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize("found", [10**100, -(10**100), "1" * 10**5, [1], {"v": 1}, None])
def test_a_behavior_file_format_of_any_json_value_is_one_line(tmp_path, found):
    data = json.loads((V1 / "behavior.json").read_text())
    path = tmp_path / "odd.json"
    path.write_text(json.dumps({**data, "format": found}))
    done = vlb("behaviors", str(path), cwd=tmp_path)
    if found is None:  # null: no format given, format 1
        assert done.returncode == 0, done.stderr
    else:
        assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
        assert len(done.stderr) < 2500 and "format" in done.stderr
